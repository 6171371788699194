proxygrasp_test(tracking tracker)
