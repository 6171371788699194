proxygrasp_test(level params)
