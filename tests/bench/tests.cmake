proxygrasp_bench(physics LIBS pg_physics)
proxygrasp_bench(proxies LIBS pg_proxies)
proxygrasp_bench(sensing LIBS pg_tracking)
proxygrasp_bench(churn LIBS pg_run)
