#include "proxygrasp/core/table.h"

namespace pg {

void Describe(TableParams& p, ParamVisitor& v) {
  v.Real("width", p.width, 1, 1000, "cm", {"table width along x", Apply::kRestart});
  v.Real("height", p.height, 1, 1000, "cm", {"table depth along y", Apply::kRestart});
  v.Real("wall_thickness", p.wallThickness, 0.1, 100, "cm",
         {"thickness of the edge walls", Apply::kRestart});
}

}  // namespace pg
