proxygrasp_test(sensing sensor)
