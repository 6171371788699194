proxygrasp_tests(sensing
  TESTS calibration synthetic_camera sensor background frame_source recorder calibrate preview tune
        depth_source depth_sensor)
