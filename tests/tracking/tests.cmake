proxygrasp_test(tracking tracker)
proxygrasp_test(tracking id_switches)
