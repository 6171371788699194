# every level in levels/ is a test, run through the same runner as `proxygrasp run`
file(GLOB PROXYGRASP_LEVELS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/levels/*.toml)
foreach(level_file ${PROXYGRASP_LEVELS})
  get_filename_component(level_name ${level_file} NAME_WE)
  add_test(NAME level.${level_name} COMMAND proxygrasp run ${level_file})
  set_tests_properties(level.${level_name} PROPERTIES LABELS "level;levels" TIMEOUT 300)
endforeach()
# the levels of issue 42 (outlines that merge and split in a grip, a velocity step) and of issue 44
# (measured heights on the depth camera) also on camera seeds 2 to 6: their expectations are
# derived for any camera noise
foreach(level_name merge_grip split_grip third_finger_merge pinched_cylinder_step hover_hand
                   hover_pass lower_onto_top lift_off_top measured_edge)
  foreach(seed 2 3 4 5 6)
    add_test(NAME level.${level_name}.seed${seed}
             COMMAND proxygrasp run ${PROJECT_SOURCE_DIR}/levels/${level_name}.toml
                     --set camera.seed=${seed})
    set_tests_properties(level.${level_name}.seed${seed}
                         PROPERTIES LABELS "level;levels" TIMEOUT 300)
  endforeach()
endforeach()
# a level on the synthetic depth camera end to end (issue 43: the depth camera's frames through the
# depth chain into tracking, proxies and physics): a fingertip pushing a box from the side, whose
# expectations hold for any camera that finds the fingertip's outline
foreach(seed 1 2 3)
  add_test(NAME level.side_push.depth.seed${seed}
           COMMAND proxygrasp run ${PROJECT_SOURCE_DIR}/levels/side_push.toml
                   --set camera.kind=depth --set camera.seed=${seed})
  set_tests_properties(level.side_push.depth.seed${seed} PROPERTIES LABELS "level;levels" TIMEOUT 300)
endforeach()
# the raycast twins of issue 44's levels: the same scripts with heights inferred, which fail where
# the paper says inference goes wrong (a hovering finger is not seen, a finger on the table inside
# a footprint lands on the top). A twin passes when the named expectation fails.
foreach(twin "hover_pass|tall moved" "lower_onto_top|topbox within" "lift_off_top|box within"
             "measured_edge|box moved")
  string(REPLACE "|" ";" twin "${twin}")
  list(GET twin 0 level_name)
  list(GET twin 1 failing)
  add_test(NAME level.${level_name}.raycast_twin
           COMMAND proxygrasp run ${PROJECT_SOURCE_DIR}/levels/${level_name}.toml
                   --set proxies.placement=raycast)
  set_tests_properties(level.${level_name}.raycast_twin PROPERTIES LABELS "level;levels"
                       TIMEOUT 300 PASS_REGULAR_EXPRESSION "FAIL  ${failing}")
endforeach()
proxygrasp_tests(run
  TESTS simulation frame_input trace expectations plan overrides runner recording tuio_input
        tuio_output)
