# The Python module (tools/python, -DMCCD_PYTHON): which interpreter it is built for, and
# whether it can be built. Included by the top CMakeLists before MCCD_PYTHON is declared.
#
# The module is built for one interpreter, the one that imports it: Python_EXECUTABLE when
# given (-DPython_EXECUTABLE=/path/to/python3), else the first of `python3` on PATH and
# Debian's /usr/bin/python3 that can import numpy, resolved to its real executable. An
# interpreter without numpy (a pyenv one, say) is passed over: Debian's python3-numpy and
# python3-pytest, installed by cmake/install-deps.sh, serve /usr/bin/python3.
#
# MCCD_PYTHON is ON by default when that interpreter, its headers (python3-dev) and pybind11
# (pybind11-dev) are found, except in sanitizer builds (-DMCCD_SANITIZE): an instrumented
# extension cannot be loaded into an uninstrumented interpreter.
set(MCCD_PYTHON_DEFAULT OFF)
if(NOT MCCD_SANITIZE)
  if(NOT Python_EXECUTABLE)
    find_program(_mccd_python3_on_path NAMES python3 NO_CACHE)
    foreach(candidate ${_mccd_python3_on_path} /usr/bin/python3)
      if(NOT EXISTS "${candidate}")
        continue()
      endif()
      execute_process(COMMAND "${candidate}" -c "import sys, numpy; print(sys.executable)"
        WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
        RESULT_VARIABLE _mccd_rc OUTPUT_VARIABLE _mccd_exe OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(_mccd_rc EQUAL 0 AND EXISTS "${_mccd_exe}")
        set(Python_EXECUTABLE "${_mccd_exe}" CACHE FILEPATH "The Python interpreter the mccd module is built for")
        break()
      endif()
    endforeach()
  endif()
  if(Python_EXECUTABLE)
    find_package(Python 3.8 COMPONENTS Interpreter Development.Module)
    if(Python_FOUND)
      set(PYBIND11_FINDPYTHON ON)
      find_package(pybind11 2.6 CONFIG QUIET)
      if(pybind11_FOUND)
        set(MCCD_PYTHON_DEFAULT ON)
      endif()
    endif()
  endif()
endif()
if(MCCD_PYTHON_DEFAULT)
  message(STATUS "mccd Python module: for ${Python_EXECUTABLE} (Python ${Python_VERSION}, pybind11 ${pybind11_VERSION})")
elseif(MCCD_SANITIZE)
  message(STATUS "mccd Python module: off by default in a sanitizer build (an instrumented module cannot be "
                 "loaded into an uninstrumented interpreter)")
else()
  message(STATUS "mccd Python module: off by default (no interpreter with numpy, Python headers and pybind11 found; "
                 "bash cmake/install-deps.sh installs them)")
endif()
