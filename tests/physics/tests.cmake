# the thread pool is private to the physics module: its test reads src/physics
proxygrasp_tests(physics
  TESTS coupling particles shapes layered_world params thread_pool
  INCLUDES ${PROJECT_SOURCE_DIR}/src/physics)
