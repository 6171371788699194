proxygrasp_tests(bench TESTS bench grasp_sweep churn)

# the Google Benchmark programs (run by hand, docs/performance.md)
proxygrasp_bench(physics LIBS pg_physics)
proxygrasp_bench(proxies LIBS pg_proxies)
proxygrasp_bench(sensing LIBS pg_bench)
proxygrasp_bench(churn LIBS pg_bench)
proxygrasp_bench(tuio LIBS pg_run)
