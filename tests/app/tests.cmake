proxygrasp_tests(app
  TESTS main cmd_params cmd_run cmd_sense cmd_calibrate cmd_tune table_view hand_input video cmd_bench
        level_search)
# The window tests (app_test.cpp and cmd_play_test.cpp, in their own executable because their
# process environment differs) open an SDL2 window on Xvfb. Under the sanitizers they run with leak detection
# on, with keep_loaded.cpp preloaded (libraries loaded at run time stay mapped, so their memory is
# not reported as leaked when SDL unloads them, and a leak names its library) and the third-party
# suppressions in lsan.supp. The preloaded library comes before the ASan runtime, hence
# verify_asan_link_order=0; it calls nothing before ASan is up.
set(PROXYGRASP_WINDOW_TEST_ENV)
if(PROXYGRASP_SANITIZE)
  add_library(pg_keep_loaded SHARED ${CMAKE_CURRENT_SOURCE_DIR}/app/keep_loaded.cpp)
  target_link_libraries(pg_keep_loaded PRIVATE ${CMAKE_DL_LIBS})
  set_target_properties(pg_keep_loaded PROPERTIES LIBRARY_OUTPUT_DIRECTORY
                                                  ${CMAKE_CURRENT_BINARY_DIR})
  set(PROXYGRASP_WINDOW_TEST_ENV
      "LD_PRELOAD=${CMAKE_CURRENT_BINARY_DIR}/libpg_keep_loaded.so"
      "ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:verify_asan_link_order=0"
      "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/app/lsan.supp:print_suppressions=0")
endif()
proxygrasp_tests(app TARGET test_app_window TESTS app cmd_play ENVIRONMENT ${PROXYGRASP_WINDOW_TEST_ENV})
if(PROXYGRASP_SANITIZE)
  add_dependencies(test_app_window pg_keep_loaded)
endif()
