proxygrasp_tests(proxies TESTS matching proxy_stage instant_proxies params)
