# cmake/vcmm_python.cmake — which Python interpreter vcmm's Python parts use: the module
# `vcmm` (python/, pybind11) is compiled for it, and the Python tests run with it.
#
# VCMM_PYTHON3 (cache, settable with -DVCMM_PYTHON3=/path/to/python): when not given, the first
# of /usr/bin/python3 (Debian's, which has python3-numpy, python3-matplotlib and python3-pytest
# from scripts/install-deps.sh) and the python3 first on PATH that can import numpy. The
# python3 first on PATH may be another interpreter without numpy (a pyenv shim, for
# instance): a module built for it could not take numpy arrays. `pip install .` (setup.py)
# passes the interpreter that runs pip. Empty when no candidate imports numpy.
if(NOT DEFINED VCMM_PYTHON3)
  set(_vcmm_python_found "")
  find_program(_vcmm_system_python3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH NO_CACHE)
  find_program(_vcmm_path_python3 NAMES python3 NO_CACHE)
  foreach(_candidate IN ITEMS "${_vcmm_system_python3}" "${_vcmm_path_python3}")
    if(_candidate AND NOT _vcmm_python_found)
      execute_process(COMMAND "${_candidate}" -c "import numpy"
                      RESULT_VARIABLE _status OUTPUT_QUIET ERROR_QUIET)
      if(_status EQUAL 0)
        set(_vcmm_python_found "${_candidate}")
      endif()
    endif()
  endforeach()
  set(VCMM_PYTHON3 "${_vcmm_python_found}" CACHE FILEPATH
      "Python interpreter (with numpy) for the vcmm module and the Python tests")
endif()
if(VCMM_PYTHON3)
  message(STATUS "vcmm: Python interpreter ${VCMM_PYTHON3}")
else()
  message(STATUS "vcmm: no python3 that imports numpy (tried /usr/bin/python3 and PATH): "
                 "the Python module and tests are off (install Debian python3 python3-numpy "
                 "or give -DVCMM_PYTHON3=...)")
endif()
