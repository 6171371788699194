proxygrasp_tests(level
  TESTS params describe level toml_reader loader read_objects read_script read_checks script find)
