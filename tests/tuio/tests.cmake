proxygrasp_test(tuio osc LIBS PkgConfig::LIBLO)
proxygrasp_test(tuio decoder)
proxygrasp_test(tuio encoder)
proxygrasp_test(tuio transport)
