proxygrasp_tests(sensing
  TESTS calibration synthetic_camera synthetic_depth sensor background highpass frame_source recorder
        calibrate preview tune depth_source depth_freenect depth_plane depth_sensor)
