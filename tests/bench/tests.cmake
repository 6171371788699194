proxygrasp_bench(sensing LIBS pg_tracking)
