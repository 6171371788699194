proxygrasp_bench(proxies LIBS pg_proxies)
