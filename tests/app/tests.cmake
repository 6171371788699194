proxygrasp_test(app main)
proxygrasp_test(app cmd_params)
proxygrasp_test(app cmd_run)
proxygrasp_test(app cmd_sense LIBS pg_sensing)
