# Registers one CTest test per GoogleTest suite of a test executable (run after it is
# built, as gtest_discover_tests does per test). Why per suite: every test process
# loads deal.II and the ~200 shared libraries under it, about a second of the dynamic
# loader's symbol lookups on a 2-vCPU machine, so 583 processes spent minutes on
# start-up alone; 123 suites spend a fifth of it. Each suite is named
# <executable>/<suite> and labelled with its executable's name and `full`; the suites
# not named in SLOW (as <executable>/<suite>) are labelled `quick` too
# (docs/extending.md, "Testing a change").
#
# A DISABLED_ test is registered on its own, disabled, so that CTest lists it as not run;
# a suite whose every test is disabled has no other entry. A test that calls
# GTEST_SKIP() leaves its suite passing, the skip printed in the suite's output (CTest's
# SKIP_REGULAR_EXPRESSION would mark the whole suite skipped, its failures too).
#
#   cmake -D EXE=<test executable> -D NAME=<its target> -D OUT=<file to write>
#         -D SLOW=<exe/suite;exe/suite...> -D TIMEOUT=<s> -P gtest_suites.cmake
cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE status
  TIMEOUT 120)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${status}):\n${listing}")
endif()
# A line holding '[' or ']' (a parameter's printed value) would split CMake's list.
string(REPLACE "[" "(" listing "${listing}")
string(REPLACE "]" ")" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(script "")
set(suites "")
foreach(line IN LISTS lines)
  # A suite's line starts at column 0 ("Suite." or "Prefix/Suite.  # TypeParam = ..."); its
  # tests' lines are indented ("  Test" or "  Test/0  # GetParam() = ...").
  if(line MATCHES "^([^ #][^ ]*)\\.( |$)")
    set(suite "${CMAKE_MATCH_1}")
    list(APPEND suites "${suite}")
    set(enabled_${suite} FALSE)
  elseif(line MATCHES "^  ([^ ]+)")
    set(test "${CMAKE_MATCH_1}")
    if(suite MATCHES "(^|/)DISABLED_" OR test MATCHES "^DISABLED_")
      string(APPEND script
        "add_test([==[${NAME}/${suite}.${test}]==] [==[${EXE}]==] [==[--gtest_filter=${suite}.${test}]==])\n"
        "set_tests_properties([==[${NAME}/${suite}.${test}]==] PROPERTIES DISABLED TRUE LABELS [==[${NAME};full]==])\n")
    else()
      set(enabled_${suite} TRUE)
    endif()
  endif()
endforeach()
foreach(suite IN LISTS suites)
  if(enabled_${suite})
    set(labels "${NAME};full")
    if(NOT "${NAME}/${suite}" IN_LIST SLOW)
      list(APPEND labels quick)
    endif()
    string(APPEND script
      "add_test([==[${NAME}/${suite}]==] [==[${EXE}]==] [==[--gtest_filter=${suite}.*]==])\n"
      "set_tests_properties([==[${NAME}/${suite}]==] PROPERTIES LABELS [==[${labels}]==] TIMEOUT ${TIMEOUT})\n")
  endif()
endforeach()
file(WRITE "${OUT}" "${script}")
