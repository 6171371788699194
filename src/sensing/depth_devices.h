// The depth sources that need a library: OpenNI2 (devices and ONI files) and libfreenect (a live
// Kinect v1). Each is built only when pkg-config finds its library (src/sensing/CMakeLists.txt);
// otherwise opening one is an Error saying the build lacks it.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/sensing/frame_source.h"

#include <memory>
#include <string>

namespace pg {

/// An OpenNI2 device ("" = any device, else its URI) or, with `file`, an ONI recording played
/// frame by frame. `spec` names it in messages.
Result<std::unique_ptr<FrameSource>> OpenOpenNi2(const std::string& uri, bool file,
                                                 const std::string& spec);

/// Kinect v1 number `index` through libfreenect, depth registered in mm.
Result<std::unique_ptr<FrameSource>> OpenFreenect(int index, const std::string& spec);

}  // namespace pg
