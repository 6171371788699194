proxygrasp_test(physics coupling)
proxygrasp_test(physics particles)
