proxygrasp_test(level params)
proxygrasp_test(level describe)
proxygrasp_test(level level)
proxygrasp_test(level script)
