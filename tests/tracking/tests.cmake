proxygrasp_tests(tracking TESTS tracker id_switches)
