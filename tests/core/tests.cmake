proxygrasp_tests(core TESTS error geometry params rng text)
