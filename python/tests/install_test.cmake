# ctest python_install: installs the component "python" of BUILD_DIR into a temporary prefix and
# imports seam from there (PYTHON, with SITE the package's directory under the prefix); the
# import must come from the prefix, not from the build tree, and pair two small tows.
#   cmake -DBUILD_DIR=... -DPYTHON=... -DSITE=... -P install_test.cmake
string(RANDOM LENGTH 8 suffix)
set(prefix "${BUILD_DIR}/python_install_test.${suffix}")
file(REMOVE_RECURSE "${prefix}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}" --component python
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(REMOVE_RECURSE "${prefix}")
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
if(IS_ABSOLUTE "${SITE}")
  set(site "${SITE}")
else()
  set(site "${prefix}/${SITE}")
endif()
set(script [=[
import os, sys
import seam
here = os.path.realpath(seam.__file__)
assert here.startswith(os.path.realpath(sys.argv[1])), here
A, B = seam.make_crossover(12, 12, 10, 12)
r = seam.pair(*A, *B)
assert r.curves and r.report["verified"], r.report
print("installed seam imported from", os.path.dirname(here), "and paired:", len(r.curves), "curve(s)")
]=])
# Run from the prefix: ctest's working directory (build/python) holds the build tree's package,
# which `python -c` would find first.
execute_process(COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${site}" PYTHONDONTWRITEBYTECODE=1
                        "${PYTHON}" -c "${script}" "${site}"
                WORKING_DIRECTORY "${prefix}"
                RESULT_VARIABLE rc)
file(REMOVE_RECURSE "${prefix}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed package failed (${rc})")
endif()
