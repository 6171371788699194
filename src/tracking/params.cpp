#include "proxygrasp/tracking/types.h"

namespace pg {

void Describe(TrackingParams& p, ParamVisitor& v) {
  v.Real("max_distance", p.maxDistance, 0, 100, "cm",
         "farthest a contact's centroid may move between frames and keep its id");
}

}  // namespace pg
