#include "proxygrasp/tracking/types.h"

namespace pg {

void Describe(TrackingParams& p, ParamVisitor& v) {
  v.Real("max_distance", p.maxDistance, 0, 100, "cm",
         "farthest a contact's centroid may move between frames and keep its id, at any frame "
         "rate");
  v.Real("max_speed", p.maxSpeed, 0, 10000, "cm/s",
         "fastest a contact's centroid may move and keep its id: the reach between frames dt "
         "apart is max(max_distance, max_speed dt)");
  v.Integer("keep_lost", p.keepLost, 0, 60, "frames",
            "frames a contact whose blob is gone continues where it was last seen before it is "
            "lifted (a blob that drops out for a frame or two keeps its id)");
  v.Real("merge_margin", p.mergeMargin, 0, 10, "cm",
         "an unmatched contact merged into a blob (a new blob split off a contact) when half its "
         "contour, moved on by its velocity, lies within this of the other's outline or inside "
         "it; grows by a quarter of the contact's travel between frames");
}

}  // namespace pg
