# What `cmake --install` puts under the prefix, and the Debian packages `cpack -G DEB` makes of it
# (docs/embedding.md, README "Install" and "Embed"):
#
#   bin/proxygrasp                         the command                     component runtime
#   share/proxygrasp/levels/, assets/      what it plays, found by name    component runtime
#   include/proxygrasp/<module>/*.h        the public headers              component dev
#   lib/<arch>/libproxygrasp_<module>.a    the pipeline's module libraries component dev
#   lib/<arch>/cmake/proxygrasp/           find_package(proxygrasp): proxygrasp::proxygrasp
#   lib/<arch>/pkgconfig/proxygrasp.pc     pkg-config --cflags --libs proxygrasp
#
# The runtime component is the Debian package proxygrasp, the dev component proxygrasp-dev.

include(CMakePackageConfigHelpers)

# The libraries an embedding program links: the pipeline driver (run) and everything under it.
# bench and app are the command's own and are not installed.
set(PROXYGRASP_INSTALLED_MODULES core tuio sensing tracking proxies physics level run)

# The public headers: the run module's Simulation, its frame input and runner, the level (file,
# parameters, script), and the stage types and classes those headers expose. Every proxygrasp
# header they include is in this list (scripts/install-test.sh compiles each installed header
# alone against the installed prefix). The others (app, bench, calibration and tuning tools, the
# TUIO output, tracking's id-switch judge, physics shapes, text helpers) stay private.
set(PROXYGRASP_PUBLIC_HEADERS
    core/error.h core/geometry.h core/ids.h core/params.h core/rng.h core/table.h core/timer.h
    core/units.h
    tuio/decoder.h tuio/encoder.h tuio/osc.h tuio/transport.h tuio/types.h
    sensing/background.h sensing/calibration.h sensing/frame_source.h sensing/highpass.h sensing/recorder.h
    sensing/depth_sensor.h sensing/sensor.h
    sensing/synthetic_camera.h sensing/types.h
    tracking/tracker.h tracking/types.h
    proxies/instant_proxies.h proxies/matching.h proxies/proxy_stage.h proxies/types.h
    physics/layered_world.h physics/types.h
    level/find.h level/level.h level/params.h level/script.h
    run/expectations.h run/frame_input.h run/overrides.h run/plan.h run/runner.h run/simulation.h
    run/trace.h run/tuio_input.h)

# the command, and the levels (with their shared includes and recordings) and assets it plays
install(TARGETS proxygrasp RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/levels/ DESTINATION ${PROXYGRASP_INSTALL_DATADIR}/levels
        COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets/ DESTINATION ${PROXYGRASP_INSTALL_DATADIR}/assets
        COMPONENT runtime)

# the module libraries as proxygrasp::<module>, files libproxygrasp_<module>.a, and one umbrella
# target proxygrasp::proxygrasp that links them all
foreach(module ${PROXYGRASP_INSTALLED_MODULES})
  set_target_properties(pg_${module} PROPERTIES OUTPUT_NAME proxygrasp_${module}
                                                EXPORT_NAME ${module})
endforeach()
add_library(proxygrasp_library INTERFACE)
set_target_properties(proxygrasp_library PROPERTIES EXPORT_NAME proxygrasp)
target_link_libraries(proxygrasp_library INTERFACE pg_run)
add_library(proxygrasp::proxygrasp ALIAS proxygrasp_library)
list(TRANSFORM PROXYGRASP_INSTALLED_MODULES PREPEND pg_ OUTPUT_VARIABLE installed_targets)
install(TARGETS ${installed_targets} proxygrasp_library EXPORT proxygraspTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
foreach(header ${PROXYGRASP_PUBLIC_HEADERS})
  get_filename_component(subdir ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/include/proxygrasp/${header}
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/proxygrasp/${subdir} COMPONENT dev)
endforeach()

# the CMake package: targets, config (which finds the dependencies) and version
set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/proxygrasp)
install(EXPORT proxygraspTargets NAMESPACE proxygrasp:: DESTINATION ${config_dir} COMPONENT dev)
# the depth cameras' pkg-config modules the sensing library was built with (PREFIX=module)
get_property(PROXYGRASP_DEPTH_PACKAGES GLOBAL PROPERTY PROXYGRASP_DEPTH_PACKAGES)
set(pc_depth_requires)
foreach(entry ${PROXYGRASP_DEPTH_PACKAGES})
  string(REGEX REPLACE "^[^=]*=" "" module ${entry})
  string(APPEND pc_depth_requires " ${module}")
endforeach()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/proxygraspConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/proxygraspConfig.cmake
                              INSTALL_DESTINATION ${config_dir}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR PROXYGRASP_INSTALL_DATADIR)
# 0.x: a minor version may change the API, so only the same minor version is compatible
write_basic_package_version_file(${PROJECT_BINARY_DIR}/proxygraspConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/proxygraspConfig.cmake
              ${PROJECT_BINARY_DIR}/proxygraspConfigVersion.cmake
        DESTINATION ${config_dir} COMPONENT dev)

# pkg-config: the libraries in dependency order, the dependencies through their own .pc files
set(pc_libs)
foreach(module run level physics proxies tracking sensing tuio core)
  string(APPEND pc_libs " -lproxygrasp_${module}")
endforeach()
# the prefix relative to the .pc file's folder (pkg-config's ${pcfiledir}), so the file moves with it
file(RELATIVE_PATH pc_prefix_from_pcdir /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/proxygrasp.pc.in ${PROJECT_BINARY_DIR}/proxygrasp.pc
               @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/proxygrasp.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
        COMPONENT dev)

# The Debian packages: proxygrasp (the command and its levels; its Depends come from
# dpkg-shlibdeps on the command) and proxygrasp-dev (headers, libraries, CMake and pkg-config
# files; it needs the dependencies' -dev packages to build against them). `cpack -G DEB` in the
# build folder writes proxygrasp_<version>_<arch>.deb and proxygrasp-dev_<version>_<arch>.deb.
set(CPACK_PACKAGE_NAME proxygrasp)
set(CPACK_PACKAGE_VENDOR "proxygrasp")
set(CPACK_PACKAGE_CONTACT "proxygrasp maintainers <proxygrasp@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Grasp virtual objects on an imaging touch table with persistent particle proxies")
set(CPACK_PACKAGE_DESCRIPTION
    "proxygrasp turns the contact shapes an imaging touch table's camera sees into physics (Box2D \
layers driven by persistent particle proxies), so people can push, drag, squeeze, turn and hold \
virtual objects. The proxygrasp command plays and checks levels; proxygrasp-dev embeds the \
pipeline in other programs.")
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME proxygrasp)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME proxygrasp-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "proxygrasp (= ${PROJECT_VERSION}), libopencv-dev (>= 4.5), libeigen3-dev (>= 3.4), \
libbox2d-dev (>= 2.4), libtomlplusplus-dev (>= 3), liblo-dev, pkg-config")
# the depth cameras' -dev packages, where the build linked them
foreach(entry ${PROXYGRASP_DEPTH_PACKAGES})
  string(REGEX REPLACE "^[^=]*=" "" module ${entry})
  string(APPEND CPACK_DEBIAN_DEV_PACKAGE_DEPENDS ", ${module}-dev")
endforeach()
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION}")
set(CPACK_COMPONENT_DEV_DESCRIPTION
    "Headers, static libraries, CMake package (find_package(proxygrasp), target \
proxygrasp::proxygrasp) and pkg-config file for embedding the proxygrasp pipeline.")
include(CPack)

# Every public header compiles alone with only the public headers on the include path: each is
# copied into build/public_include and included by a translation unit of its own, built with the
# rest (through ccache, so a rebuild costs nothing). A public header that includes a private one,
# or leans on something it does not include, fails the build here rather than an embedder's.
# Checked in the plain builds only: the sanitizers change nothing about what a header includes.
if(NOT PROXYGRASP_SANITIZE)
  set(header_check_sources)
  foreach(header ${PROXYGRASP_PUBLIC_HEADERS})
    configure_file(${PROJECT_SOURCE_DIR}/include/proxygrasp/${header}
                   ${PROJECT_BINARY_DIR}/public_include/proxygrasp/${header} COPYONLY)
    string(REPLACE "/" "_" stem ${header})
    string(REPLACE ".h" "" stem ${stem})
    set(source ${PROJECT_BINARY_DIR}/header_check/${stem}.cpp)
    file(CONFIGURE OUTPUT ${source} CONTENT "#include <proxygrasp/${header}>\n")
    list(APPEND header_check_sources ${source})
  endforeach()
  add_library(proxygrasp_header_check OBJECT ${header_check_sources})
  target_include_directories(proxygrasp_header_check PRIVATE ${PROJECT_BINARY_DIR}/public_include)
  target_link_libraries(proxygrasp_header_check PRIVATE Eigen3::Eigen opencv_core opencv_videoio
                                                        proxygrasp_options)
endif()
