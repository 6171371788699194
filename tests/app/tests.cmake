proxygrasp_test(app main)
proxygrasp_test(app cmd_params)
