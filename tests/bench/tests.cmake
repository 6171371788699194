proxygrasp_bench(physics LIBS pg_physics)
