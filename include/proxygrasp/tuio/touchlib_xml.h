// Recorded TUIO streams in touchlib's XML form: each OSC packet written out as an <OSCPACKET>
// element holding <MESSAGE NAME="/tuio/2Dcur"> elements, each holding <ARGUMENT TYPE="f"
// VALUE="0.32"/> elements. Read with a small tag scanner into the OSC structs the decoder takes.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/tuio/osc.h"

#include <string>
#include <string_view>
#include <vector>

namespace pg {

/// The packets of a touchlib XML recording, in file order, one bundle each (TIME, the raw 64-bit
/// OSC time tag, becomes the bundle's time). Argument types i, h, f, d, s and S keep their values;
/// T, F, N and I carry none. An Error reads "file:line:col: message"; nothing is half-read.
/// `file` names the text in errors.
Result<std::vector<OscBundle>> ParseTouchlibXml(std::string_view text, const std::string& file);

/// ParseTouchlibXml on the contents of a file; an Error when it cannot be read.
Result<std::vector<OscBundle>> ReadTouchlibXml(const std::string& path);

}  // namespace pg
