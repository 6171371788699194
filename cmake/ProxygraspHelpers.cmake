# Shared build settings and the helpers every module uses.

# compile options for all project targets
add_library(proxygrasp_options INTERFACE)
target_compile_options(proxygrasp_options INTERFACE -Wall -Wextra -Wpedantic)
# GCC 12 reports false -Wrestrict errors inside libstdc++ for plain `"a" + std::string` at -O2
# (GCC bug 105651, fixed in GCC 13); everything else stays on
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(proxygrasp_options INTERFACE -Wno-restrict)
endif()
if(PROXYGRASP_WERROR)
  target_compile_options(proxygrasp_options INTERFACE -Werror)
endif()
if(PROXYGRASP_SANITIZE)
  target_compile_options(proxygrasp_options INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                      -fno-sanitize-recover=undefined)
  target_link_options(proxygrasp_options INTERFACE -fsanitize=address,undefined)
endif()

# proxygrasp_module(name SOURCES ... DEPS ...): one CMake library per module, target pg_<name>.
# Public headers live in include/proxygrasp/<name>/, private ones beside the sources.
function(proxygrasp_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(pg_${name} STATIC ${ARG_SOURCES})
  target_include_directories(pg_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include
                                        PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(pg_${name} PUBLIC ${ARG_DEPS} PRIVATE proxygrasp_options)
endfunction()

# proxygrasp_test(module name [LIBS ...] [ENVIRONMENT VAR=value ...]): builds tests/<module>/<name>_test.cpp into one GoogleTest
# executable and registers each of its tests with CTest, labelled with the module.
function(proxygrasp_test module name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "LIBS;ENVIRONMENT" ${ARGN})
  set(target test_${module}_${name})
  add_executable(${target} ${CMAKE_CURRENT_SOURCE_DIR}/${module}/${name}_test.cpp)
  if(TARGET pg_${module})
    target_link_libraries(${target} PRIVATE pg_${module})
  endif()
  target_link_libraries(${target} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main
                                          proxygrasp_options)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/include
                                               ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_definitions(${target} PRIVATE
    PROXYGRASP_TESTDATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/${module}/testdata"
    PROXYGRASP_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    PROXYGRASP_BIN="$<TARGET_FILE:proxygrasp>")
  add_dependencies(${target} proxygrasp)
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  gtest_discover_tests(${target} DISCOVERY_MODE PRE_TEST
                       PROPERTIES LABELS ${module} TIMEOUT ${ARG_TIMEOUT})
  if(ARG_ENVIRONMENT)
    # gtest_discover_tests flattens its PROPERTIES, which keeps only the first variable of an
    # ENVIRONMENT list: set the variables on the discovered tests (${target}_TESTS) instead, from a
    # file CTest includes after the one that discovers them
    set(environment_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_environment.cmake)
    file(WRITE ${environment_file}
         "if(${target}_TESTS)\n"
         "  set_tests_properties(\${${target}_TESTS} PROPERTIES ENVIRONMENT\n"
         "                       [==[${ARG_ENVIRONMENT}]==])\n"
         "endif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${environment_file})
  endif()
endfunction()

# proxygrasp_bench(name LIBS ...): builds tests/bench/<name>_bench.cpp with Google Benchmark into
# bench_<name> at the top of the build tree. Benchmarks are run by hand (see docs/performance.md),
# never as timed tests.
function(proxygrasp_bench name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  if(NOT PROXYGRASP_BUILD_BENCH)
    return()
  endif()
  find_package(benchmark REQUIRED)
  set(target bench_${name})
  add_executable(${target} ${CMAKE_CURRENT_SOURCE_DIR}/bench/${name}_bench.cpp)
  target_link_libraries(${target} PRIVATE ${ARG_LIBS} benchmark::benchmark proxygrasp_options)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/include
                                               ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_definitions(${target} PRIVATE PROXYGRASP_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  set_target_properties(${target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR})
endfunction()
