proxygrasp_test(proxies matching)
proxygrasp_test(proxies proxy_stage)
proxygrasp_test(proxies instant_proxies)
proxygrasp_test(proxies params)
