# Decides whether the Python module is built (option MTCAL_PYTHON) and finds what it needs: a Python 3
# interpreter that imports NumPy, its development files (Python3::Module) and pybind11's CMake package.
# Default: ON when all are found, OFF (with the reason) otherwise; -DMTCAL_PYTHON=ON makes a missing piece
# an error, -DMTCAL_PYTHON=OFF skips the search. -DPython3_EXECUTABLE=... picks the interpreter.

set(_mtcal_python_missing "")
if(NOT DEFINED MTCAL_PYTHON OR MTCAL_PYTHON)
  if(MTCAL_SANITIZE AND NOT DEFINED MTCAL_PYTHON)
    # A sanitized module needs the sanitizer runtime preloaded into the interpreter: not by default.
    set(_mtcal_python_missing "MTCAL_SANITIZE is ON")
  else()
    if(NOT DEFINED Python3_EXECUTABLE)
      # Debian's python3-numpy, -pytest and -matplotlib belong to Debian's interpreter. An interpreter first on
      # PATH (pyenv, a virtual environment) may lack them: take the first of `python3` on PATH and
      # /usr/bin/python3 that imports all three (the module, its tests, its examples), else the first that
      # imports NumPy (the module alone).
      find_program(_mtcal_python3_on_path NAMES python3 NO_CACHE)
      foreach(imports "numpy, pytest, matplotlib" "numpy")
        foreach(candidate ${_mtcal_python3_on_path} /usr/bin/python3)
          if(NOT DEFINED Python3_EXECUTABLE AND EXISTS ${candidate})
            execute_process(COMMAND ${candidate} -c "import ${imports}" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
            if(rc EQUAL 0)
              set(Python3_EXECUTABLE ${candidate} CACHE FILEPATH "Python interpreter of the mtcal module")
            endif()
          endif()
        endforeach()
      endforeach()
    endif()
    find_package(Python3 3.8 QUIET COMPONENTS Interpreter Development.Module)
    if(NOT Python3_Interpreter_FOUND)
      set(_mtcal_python_missing "no Python 3 interpreter")
    elseif(NOT Python3_Development.Module_FOUND)
      set(_mtcal_python_missing "no Python development files for ${Python3_EXECUTABLE} (Debian: python3-dev)")
    else()
      execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
      if(NOT rc EQUAL 0)
        set(_mtcal_python_missing "${Python3_EXECUTABLE} cannot import numpy (Debian: python3-numpy)")
      else()
        find_package(pybind11 2.6 CONFIG QUIET)
        if(NOT pybind11_FOUND)
          set(_mtcal_python_missing "no pybind11 CMake package (Debian: pybind11-dev)")
        endif()
      endif()
    endif()
  endif()
endif()

if(NOT DEFINED MTCAL_PYTHON)
  if(_mtcal_python_missing)
    message(STATUS "Python module mtcal: not built (${_mtcal_python_missing})")
    set(_mtcal_python_default OFF)
  else()
    set(_mtcal_python_default ON)
  endif()
  option(MTCAL_PYTHON "Build the Python module mtcal (pybind11)" ${_mtcal_python_default})
elseif(MTCAL_PYTHON AND _mtcal_python_missing)
  message(FATAL_ERROR "MTCAL_PYTHON is ON but ${_mtcal_python_missing}")
endif()
