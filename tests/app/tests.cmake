proxygrasp_test(app main)
proxygrasp_test(app cmd_params)
proxygrasp_test(app cmd_sense LIBS pg_sensing)
proxygrasp_test(app cmd_calibrate LIBS pg_sensing)
