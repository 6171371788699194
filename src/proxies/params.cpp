#include "proxygrasp/proxies/types.h"

namespace pg {

void Describe(ProxyParams& p, ParamVisitor& v) {
  VisitEnum(v, "mode", p.mode, kProxyModeNames,
            "persistent particle proxies, or per-frame (instant) particles");
  VisitEnum(v, "algorithm", p.algorithm, kMatchAlgorithmNames, "successor search algorithm");
  v.Integer("window", p.window, 0, 64, "points", "n, contour points summed around each match");
  v.Boolean("subsample", p.subsample,
            "refine each reused particle's target between contour samples, so slow motion along "
            "the contour is followed smoothly instead of in hops of one sample");
  v.Integer("count_hysteresis", p.countHysteresis, 0, 16, "points",
            "a continuing contact keeps its point count while sensing's count differs from it by "
            "at most this many points (fast and windowed searches; sensing noise then creates "
            "and deletes no particles)");
  v.Integer("search_radius", p.searchRadius, 1, 512, "points",
            "w, half-width of the windowed search around the predicted offset");
  v.Real("fallback_score", p.fallbackScore, 0, 100, "cm^2",
         "windowed search falls back to the full search where its best exceeds a lower bound "
         "on the exact score by more than this per window term");
  VisitEnum(v, "placement", p.placement, kPlacementNames,
            "new contacts by raycast onto the highest surface, on the table outside every "
            "footprint (ground), or at the heights a depth camera measured where a contact has "
            "them and by raycast where it has none (measured, auto)");
  v.Real("height_offset", p.heightOffset, 0, 10, "cm",
         "measured: how far below a contour point's measured height (the top of the finger near "
         "its outline) the finger's underside lies");
  v.Integer("height_span", p.heightSpan, 0, 16, "points",
            "measured: a particle's height is the median over the contour points this many "
            "either side of its own");
  v.Real("height_smoothing", p.heightSmoothing, 0, 1, "s",
         "measured: time constant of the filter each particle's measured height passes (0 = "
         "none)");
  v.Real("penetration_limit", p.penetrationLimit, 0, 100, "cm",
         "ground mode: a new contact whose deepest contour point lies deeper than this inside an "
         "object's footprint is placed by raycast (on the top) instead of on the table");
  v.Real("instant_threshold", p.instantThreshold, 0, 2000, "grey/px",
         "instant mode: Sobel magnitude that makes a particle");
  v.Real("instant_spacing", p.instantSpacing, 0.05, 5, "cm",
         "instant mode: spacing of the subsampled particles");
  v.Integer("instant_flow_window", p.instantFlowWindow, 5, 101, "px",
            "instant mode: window of the Lucas-Kanade optical flow that moves each particle");
}

}  // namespace pg
