proxygrasp_test(physics coupling)
proxygrasp_test(physics particles)
proxygrasp_test(physics shapes)
proxygrasp_test(physics layered_world)
proxygrasp_test(physics params)
proxygrasp_test(physics thread_pool)
# the pool is private to the physics module
target_include_directories(test_physics_thread_pool PRIVATE ${PROJECT_SOURCE_DIR}/src/physics)
