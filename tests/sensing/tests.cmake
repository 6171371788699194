proxygrasp_test(sensing calibration)
proxygrasp_test(sensing synthetic_camera)
proxygrasp_test(sensing sensor)
proxygrasp_test(sensing frame_source)
