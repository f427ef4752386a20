# ctest install_consumer: installs the build into a staging prefix, then configures, builds and
# runs tests/install/consumer against it (find_package(mtcal) from the staged prefix only).
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -DCXX=... -DMACHINE=...
#       [-DSANITIZE=ON] -P run_consumer.cmake
# SANITIZE: the library was built with -fsanitize=address,undefined, so the consumer links the runtimes.
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR CXX MACHINE)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_consumer.cmake: ${v} is not set")
  endif()
endforeach()
set(stage ${WORK_DIR}/stage)
set(consumer_build ${WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${stage} ${consumer_build})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(JOIN " " cmd ${ARGN})
    message(FATAL_ERROR "failed (${rc}): ${cmd}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${stage})
file(GLOB_RECURSE templates ${stage}/*.in)
if(templates)
  message(FATAL_ERROR "template files installed: ${templates}")
endif()
foreach(f include/mtcal/version.hpp)
  if(NOT EXISTS ${stage}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
set(sanitize_flags)
if(SANITIZE)
  set(sanitize_flags -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined)
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/consumer -B ${consumer_build} -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${stage}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF ${sanitize_flags})
run(${CMAKE_COMMAND} --build ${consumer_build})
run(${consumer_build}/consumer ${MACHINE})
