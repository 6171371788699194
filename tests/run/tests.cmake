# every level in levels/ is a test, run through the same runner as `proxygrasp run`
file(GLOB PROXYGRASP_LEVELS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/levels/*.toml)
foreach(level_file ${PROXYGRASP_LEVELS})
  get_filename_component(level_name ${level_file} NAME_WE)
  add_test(NAME level.${level_name} COMMAND proxygrasp run ${level_file})
  set_tests_properties(level.${level_name} PROPERTIES LABELS "level;levels" TIMEOUT 300)
endforeach()
proxygrasp_tests(run
  TESTS simulation frame_input trace expectations plan overrides runner recording tuio_input
        tuio_output)
