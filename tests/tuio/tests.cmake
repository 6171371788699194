proxygrasp_tests(tuio TESTS osc decoder encoder transport touchlib_xml LIBS PkgConfig::LIBLO)
