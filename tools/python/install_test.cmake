# The documented install of the Python module, checked without touching the system: the
# `python` component staged under DESTDIR, then imported by the same interpreter from another
# folder with only the staged site-packages on its path.
#   -DBUILD_DIR= -DWORK_DIR= -DPYTHON= -DINSTALL_DIR= -DVERSION=
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
set(ENV{DESTDIR} ${WORK_DIR}/stage)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component python RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "cmake --install --component python failed: ${rc}")
endif()
set(site ${WORK_DIR}/stage${INSTALL_DIR})
foreach(f __init__.py __init__.pyi py.typed)
  if(NOT EXISTS ${site}/mccd/${f})
    message(FATAL_ERROR "not installed: ${site}/mccd/${f}")
  endif()
endforeach()
set(ENV{PYTHONPATH} ${site})
execute_process(COMMAND ${PYTHON} -c "import mccd; print(mccd.__version__); print(mccd.__file__)"
  WORKING_DIRECTORY ${WORK_DIR}/elsewhere RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "importing the installed module failed: ${err}")
endif()
if(NOT out STREQUAL "${VERSION}\n${site}/mccd/__init__.py\n")
  message(FATAL_ERROR "unexpected output (version, then the module's file): ${out}")
endif()
message(STATUS "installed and imported: ${out}")
