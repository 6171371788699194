proxygrasp_test(tuio osc LIBS PkgConfig::LIBLO)
proxygrasp_test(tuio decoder)
