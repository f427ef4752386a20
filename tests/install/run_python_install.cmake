# ctest python_install: installs the build into a staging prefix and imports the Python package from there
# alone (a fresh interpreter, PYTHONPATH = the staged site directory, the build tree not on the path).
# cmake -DBUILD_DIR=... -DWORK_DIR=... -DPYTHON=... -DSITE=<install dir of the package> -DMACHINE=... -P this
foreach(v BUILD_DIR WORK_DIR PYTHON SITE MACHINE)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_python_install.cmake: ${v} is not set")
  endif()
endforeach()
set(stage ${WORK_DIR}/stage)
file(REMOVE_RECURSE ${stage})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(JOIN " " cmd ${ARGN})
    message(FATAL_ERROR "failed (${rc}): ${cmd}")
  endif()
endfunction()

# An absolute SITE (set by the user) would be written outside the stage: stage it under DESTDIR instead.
if(IS_ABSOLUTE "${SITE}")
  run(${CMAKE_COMMAND} -E env DESTDIR=${stage} ${CMAKE_COMMAND} --install ${BUILD_DIR} --component python)
  set(site ${stage}${SITE})
else()
  run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${stage} --component python)
  set(site ${stage}/${SITE})
endif()
foreach(f __init__.py __init__.pyi _mtcal.pyi py.typed)
  if(NOT EXISTS ${site}/mtcal/${f})
    message(FATAL_ERROR "not installed: ${site}/mtcal/${f}")
  endif()
endforeach()
file(GLOB ext ${site}/mtcal/_mtcal*.so)
if(NOT ext)
  message(FATAL_ERROR "the extension module is not installed in ${site}/mtcal")
endif()
# -I: isolated from the user's site and PYTHON* variables; the staged directory is the only addition.
set(check [=[
import sys
sys.path.insert(0, sys.argv[1])
import mtcal, numpy as np
assert mtcal.__file__.startswith(sys.argv[1]), mtcal.__file__
m = mtcal.Machine.load(sys.argv[2])
e = mtcal.evaluate(m, np.zeros((4, m.axis_count)))
assert e.shape == (4, 6)
print("imported", mtcal.__version__, "from", mtcal.__file__)
]=])
run(${PYTHON} -I -c "${check}" ${site} ${MACHINE})
