// Contour matching (ALGORITHM section of the ITS 2009 paper): each point k of the previous contour
// gets the successor j* on the current contour that minimises the summed squared distance of the
// n+1 points around them,
//   j* = argmin_j sum_{i=-n/2..n/2} |prev(k+i) - cur(j+i)|^2,
// both contours indexed cyclically in their own lengths. Three searches return it: the exhaustive
// reference, a fast exact search (running sums along the diagonals, O(N M + M n)) that returns the
// same successors and scores bit for bit, and a windowed search around predicted successors
// (O(N w)) that falls back to the full search where its answer looks wrong.
//
// Exactness: every version quantizes coordinates to kMatchQuantum and sums squared distances in
// 64-bit integers, so no version depends on the order of its additions. Ties break to the lowest j.
#pragma once

#include "proxygrasp/core/geometry.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace pg {

/// Fixed-point step of the matching arithmetic, cm. Coordinates are rounded to it.
inline constexpr double kMatchQuantum = 1e-4;
/// Coordinates are clamped to +-kMatchCoordLimit cm before quantizing (keeps the sums in int64).
inline constexpr double kMatchCoordLimit = 1e4;
/// Largest window n any search accepts, points (keeps the sums in int64).
inline constexpr int kMaxMatchWindow = 64;

/// Successor of every previous point and its score.
struct MatchResult {
  std::vector<int> successor;  ///< per previous point k: index j into the current contour
  std::vector<double> score;   ///< per previous point: the summed squared distance at j*, cm^2
  int fallbacks = 0;           ///< windowed search only: points answered by the full search
};

/// Exhaustive reference search, O(N M n). window is n (0..kMaxMatchWindow); the sum runs over
/// i = -n/2..n/2. An empty cur gives successor -1 and an infinite score for every point.
MatchResult MatchReference(const Contour& prev, const Contour& cur, int window);

/// Fast exact search, O(N M + M n): the same successors and scores as MatchReference.
MatchResult MatchFast(const Contour& prev, const Contour& cur, int window);

/// Windowed search around per-point predicted successors: point k only considers the 2*radius+1
/// current points around predicted[k] (predicted.size() must equal prev.cols()); runs of 32
/// points share one diagonal band, so the band costs O(N w). A point is answered by the full search
/// instead when its band's best lies on the band's edge (the score still falls outward), or when
/// the best exceeds a lower bound on the full search's score (every window point on its nearest
/// current point) by more than fallbackScore per window term (cm^2): so every point the band
/// answers scores within fallbackScore per term of the exact answer. When the fallbacks would
/// cost more than the fast search of the whole contour, the whole contour is searched.
/// fellBack (when given) is set when any point fell back.
MatchResult MatchWindowed(const Contour& prev, const Contour& cur, int window,
                          std::span<const int> predicted, int radius, double fallbackScore,
                          bool* fellBack = nullptr);

/// True when the windowed search's band of 2 radius + 1 points spans a current contour of
/// `currentPoints` (a fingertip's): MatchWindowed is then the full search (MatchFast), every point
/// counted as handed to it, and needs no prediction.
inline bool BandSpansContour(int radius, int currentPoints) {
  return 2 * std::max(radius, 0) + 1 >= currentPoints;
}

/// Windowed search with a linear prediction: predicted[k] = predictedOffset + round(k M / N),
/// wrapped into [0, M).
MatchResult MatchWindowed(const Contour& prev, const Contour& cur, int window, int predictedOffset,
                          int radius, double fallbackScore, bool* fellBack = nullptr);

/// Predicts each previous point's successor from the contact's motion: a rigid motion estimated
/// from the two contours (centroid displacement, plus the turn of the principal axis when the
/// shape is elongated) moves the previous point, and its nearest current point, found by a local
/// descent along the current contour from the last point's answer, is the prediction. O(N + M).
std::vector<int> PredictSuccessors(const Contour& prev, const Contour& cur);

/// A contact's rigid motion from its previous contour to its current one.
struct ContourMotion {
  Pose2 motion;  ///< maps a previous point to where it is now (turn about the origin)
  bool turnObservable = false;  ///< the outline shows its turning (not round)
  double residual = 0.0;        ///< RMS distance of the moved previous points to the current
                                ///< contour, cm
};

/// Estimates the rigid motion that carries prev onto cur: seeded by the centroid shift and, for an
/// elongated outline, the turn of its principal axis, then refined by a few iterations of
/// point-to-line alignment (each moved previous point against the nearest segment of cur, points
/// far off the contour weighted down, so a local shape change does not pull the estimate). The
/// turn is damped where the outline cannot show it: a round contour translates only. O(N + M) per
/// iteration. Both contours must be wound the same way (sensing makes them counter-clockwise).
ContourMotion EstimateMotion(const Contour& prev, const Contour& cur);

/// The motion of a piece of an outline, the points of one finger of a merged contact (each of
/// its fingers moves its own way, and the merged outline's one motion is none of theirs):
/// `seed` (the whole outline's motion) with its shift refined by the point-to-line alignment of
/// EstimateMotion, of the piece against the whole current contour; the turn stays the seed's.
/// Points that went inside the outline (where the finger now touches another) are weighted down
/// as any local change of shape is. The seed when the piece has fewer than 3 points.
Pose2 EstimatePieceMotion(const Contour& piece, const Contour& cur, const Pose2& seed);

/// prev moved by motion (every point through motion.Apply).
Contour Transformed(const Contour& prev, const Pose2& motion);

/// cur resampled to `count` points evenly spaced by arc length, in phase with `reference` (prev
/// moved onto cur): the common phase is the median, over the reference points, of the offset
/// between where reference point k projects onto cur and where output point k would lie, so that
/// under rigid motion output point k lies where reference point k projects. O(N + M).
Contour ResampleInPhase(const Contour& cur, const Contour& reference, int count);

/// Predecessor of every current point: the previous point that chose it as successor with the
/// lowest score (ties to the lowest k), or -1 when none chose it.
std::vector<int> Predecessors(const MatchResult& match, int currentCount);

}  // namespace pg
