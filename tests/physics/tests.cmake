proxygrasp_test(physics coupling)
