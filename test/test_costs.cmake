# Included by ctest after the discovered tests (TEST_INCLUDE_FILES): the tests known to take
# longest start first. ctest -j2 starts the costliest tests first, but a clean checkout has no
# timing history, and a long test started last runs alone on one core while the other idles.
# Costs are seconds measured under the sanitizers (the Release run has the same order). Tests
# added with add_test set their COST where they are added.
set(seam_long_tests
  "contract: SIGINT or SIGTERM at any moment leaves no temporary file and never mixes old and new outputs=40"
  "real-like: seam check and tetgen -d agree on every pair, passing or failing=35"
  "real-like: a terraced tow against turned and shifted copies comes out conforming, flat contacts shared=30"
  "pair: crossing tows come out conforming along their intersection curves - seam::Exact=25"
  "contract: every numeric option refuses NaN, infinity, negative and out-of-range values with exit 2=22"
  "pair with given curves: the smooth analytic intersection, off the facets, is embedded into both=22"
  "pair with given curves: the intersection given as the curves comes out conforming=20"
  "textile: tetgen finds no intersecting faces in the whole cell once embedded=17"
  "contract: a bad mesh in any input position of embed, pair or check gives exit 2 naming it=17"
  "pair: with no tolerance the quality stage keeps both surfaces: each input face's vector area is kept=16"
  "pair robustness: under the filtered kernel a crossing whose rounded determinants agree is constructed exactly, not as NaN=16")
foreach(entry IN LISTS seam_long_tests)
  string(REGEX REPLACE "=[0-9]+$" "" name "${entry}")
  string(REGEX REPLACE "^.*=" "" cost "${entry}")
  set_tests_properties("${name}" PROPERTIES COST "${cost}")
endforeach()
