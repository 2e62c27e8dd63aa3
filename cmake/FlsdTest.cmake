include(GoogleTest)

# Test sources compile at -O1: gtest's macros are slow to optimise, and the code under test is the
# project's libraries, which keep the build type's -O3 (measured: tests/server/controller_test.cc
# 12.5 s at -O3, 8.1 s at -O1). Targets that reuse libtorch's precompiled header keep -O3, which
# GCC needs to use it (flsd_reuse_torch_pch).
set(FLSD_TEST_OPTIMIZATION -O1)

# flsd_test(NAME SOURCE LABEL [RUN_SERIAL] [LIBS...]): one gtest executable whose cases are
# registered with ctest under LABEL (unit or integration), so `ctest -L unit` selects the fast
# ones. RUN_SERIAL is for cases that measure a real-time rate: on two cores, a test running beside
# them takes the CPU their threads need, and the rate they measure is then the neighbour's.
function(flsd_test name source label)
  cmake_parse_arguments(arg "RUN_SERIAL" "" "" ${ARGN})
  add_executable(${name} ${source})
  target_compile_options(${name} PRIVATE ${FLSD_TEST_OPTIMIZATION})
  target_link_libraries(${name} PRIVATE GTest::gtest_main ${arg_UNPARSED_ARGUMENTS})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  gtest_discover_tests(${name} PROPERTIES LABELS ${label} RUN_SERIAL ${arg_RUN_SERIAL} DISCOVERY_TIMEOUT 60)
endfunction()

# flsd_torch_test(NAME SOURCE LABEL [LIBS...]): as flsd_test, but the whole executable is one ctest
# test. Loading libtorch costs about a second per process, more than all the cases of these files
# take together, so they run in one process each (ctest -V, or the executable, lists the cases).
function(flsd_torch_test name source label)
  add_executable(${name} ${source})
  target_link_libraries(${name} PRIVATE GTest::gtest_main ${ARGN})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  flsd_reuse_torch_pch(${name})
  add_test(NAME ${name} COMMAND ${name})
  set_tests_properties(${name} PROPERTIES LABELS ${label})
endfunction()
