// The table surface, shared by sensing (image-to-table mapping) and physics (walls).
#pragma once

#include "proxygrasp/core/params.h"

namespace pg {

/// The table surface, x to the right and y up, origin at the bottom-left corner. Section [table]
/// of a level. Defaults suit a 30" 4:3 table.
struct TableParams {
  double width = 61.0;         ///< along x, cm
  double height = 46.0;        ///< along y, cm
  double wallThickness = 2.0;  ///< thickness of the walls at the edges, cm
};

void Describe(TableParams& p, ParamVisitor& v);

}  // namespace pg
