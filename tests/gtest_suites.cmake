# Registers one CTest test per GoogleTest suite of a test executable (run after it is
# built, as gtest_discover_tests does per test). Why per suite: every test process
# loads deal.II and the ~200 shared libraries under it, about a second of the dynamic
# loader's symbol lookups on a 2-vCPU machine, so 583 processes spent minutes on
# start-up alone; 123 suites spend a fifth of it. Each suite is labelled with its
# executable's name and `full`; the suites not named in SLOW are labelled `quick` too
# (docs/extending.md, "Testing a change").
#
#   cmake -D EXE=<test executable> -D NAME=<its target> -D OUT=<file to write>
#         -D SLOW=<suite;suite...> -D TIMEOUT=<s> -P gtest_suites.cmake
cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE status
  TIMEOUT 120)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${status}):\n${listing}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(script "")
foreach(line IN LISTS lines)
  # A suite's line starts at column 0 ("Suite." or "Prefix/Suite.  # TypeParam = ..."); its
  # tests' lines are indented.
  if(line MATCHES "^([^ #][^ ]*)\\.( |$)")
    set(suite "${CMAKE_MATCH_1}")
    set(labels "${NAME};full")
    if(NOT suite IN_LIST SLOW)
      list(APPEND labels quick)
    endif()
    string(APPEND script
      "add_test([==[${NAME}/${suite}]==] [==[${EXE}]==] [==[--gtest_filter=${suite}.*]==])\n"
      "set_tests_properties([==[${NAME}/${suite}]==] PROPERTIES LABELS [==[${labels}]==] TIMEOUT ${TIMEOUT})\n")
  endif()
endforeach()
file(WRITE "${OUT}" "${script}")
