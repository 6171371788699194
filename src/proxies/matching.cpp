#include "proxygrasp/proxies/matching.h"

#include "proxygrasp/core/units.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace pg {
namespace {

// the windowed search follows one diagonal per run of this many previous points
constexpr int kSegmentLength = 32;
// a shape counts as elongated (its principal axis can show a turn) above this axis ratio
constexpr double kElongation = 1.3;
// the predicted successor's local descent also tries this many points either side of its start
constexpr int kDescentReach = 3;
// a foot found by walking along the contour (Feet) that lies farther than this many of the
// contour's mean spacings is searched for again over the whole contour
constexpr double kFootRecheck = 2.0;
// the nearest-point grid has at most this many cells along a side
constexpr int64_t kGridCells = 256;

// A contour in fixed point: coordinates in units of kMatchQuantum.
struct Fixed {
  std::vector<int64_t> x;
  std::vector<int64_t> y;
  int size() const { return static_cast<int>(x.size()); }
};

int64_t Quantize(double v) {
  // clamping keeps every window sum below 2^63 (see kMatchCoordLimit and kMaxMatchWindow)
  const double clamped = std::clamp(v, -kMatchCoordLimit, kMatchCoordLimit);
  return std::llround(clamped / kMatchQuantum);
}

Fixed ToFixed(const Contour& c) {
  Fixed f;
  f.x.resize(c.cols());
  f.y.resize(c.cols());
  for (int i = 0; i < c.cols(); ++i) {
    // NaN would make llround undefined; it is matched as the origin instead
    const double x = std::isfinite(c(0, i)) ? c(0, i) : 0.0;
    const double y = std::isfinite(c(1, i)) ? c(1, i) : 0.0;
    f.x[i] = Quantize(x);
    f.y[i] = Quantize(y);
  }
  return f;
}

// squared distance between a[i] and b[j] in quantum^2
inline int64_t Dist2(const Fixed& a, int i, const Fixed& b, int j) {
  const int64_t dx = a.x[i] - b.x[j];
  const int64_t dy = a.y[i] - b.y[j];
  return dx * dx + dy * dy;
}

// i wrapped into [0, m), cheap when i is at most one lap out
inline int WrapNear(int i, int m) {
  if (i >= m) i -= m;
  if (i < 0) i += m;
  return i >= 0 && i < m ? i : WrapIndex(i, m);
}

double ToCm2(int64_t s) {
  return static_cast<double>(s) * (kMatchQuantum * kMatchQuantum);
}

int HalfWindow(int window) {
  assert(window >= 0 && window <= kMaxMatchWindow && "window must be in 0..kMaxMatchWindow");
  return std::clamp(window, 0, kMaxMatchWindow) / 2;
}

MatchResult EmptyCurrent(int n) {
  MatchResult r;
  r.successor.assign(n, -1);
  r.score.assign(n, std::numeric_limits<double>::infinity());
  return r;
}

// the window sum of pair (k, j), computed directly
int64_t WindowSum(const Fixed& p, const Fixed& c, int k, int j, int half) {
  const int n = p.size();
  const int m = c.size();
  int a = WrapIndex(k - half, n);
  int b = WrapIndex(j - half, m);
  int64_t s = 0;
  for (int i = -half; i <= half; ++i) {
    s += Dist2(p, a, c, b);
    if (++a == n) a = 0;
    if (++b == m) b = 0;
  }
  return s;
}

// exact successors of the previous points k0..k1-1 into r, O(M (k1 - k0 + n)). diag[d] is the
// window sum of the pair (k, (k + d) mod M) for the current k: running sums along the diagonals.
// Each previous index p (unwrapped) has a row q_p[d] = Dist2(p mod N, (p + d) mod M), kept in a
// ring of n + 1 rows while it lies inside the window.
void FastRange(const Fixed& p, const Fixed& c, int half, int k0, int k1, MatchResult& r) {
  const int n = p.size();
  const int m = c.size();
  const int terms = 2 * half + 1;
  if (k0 >= k1) return;
  std::vector<int64_t> ring(static_cast<size_t>(terms) * m);
  std::vector<int64_t> diag(m, 0);
  auto rowOf = [&](int pu) { return ring.data() + static_cast<size_t>(WrapIndex(pu, terms)) * m; };
  // calls f(d, j) for d = 0..M-1 with j = (pu + d) mod M, in two unwrapped runs
  auto forRow = [&](int pu, auto&& f) {
    const int off = WrapIndex(pu, m);
    for (int d = 0; d < m - off; ++d) f(d, d + off);
    for (int d = m - off; d < m; ++d) f(d, d + off - m);
  };

  // the first window: rows k0-half..k0+half
  for (int pu = k0 - half; pu <= k0 + half; ++pu) {
    const int a = WrapIndex(pu, n);
    int64_t* row = rowOf(pu);
    forRow(pu, [&](int d, int j) {
      row[d] = Dist2(p, a, c, j);
      diag[d] += row[d];
    });
  }

  for (int k = k0; k < k1; ++k) {
    // slide every diagonal one step: row k-1-half leaves, row k+half enters (same ring slot)
    if (k > k0) {
      const int pu = k + half;
      const int a = WrapIndex(pu, n);
      int64_t* row = rowOf(pu);
      forRow(pu, [&](int d, int j) {
        const int64_t q = Dist2(p, a, c, j);
        diag[d] += q - row[d];
        row[d] = q;
      });
    }
    // argmin in increasing j so ties go to the lowest j: j = (k + d) mod M
    const int s = k % m;
    int bestJ = -1;
    int64_t best = std::numeric_limits<int64_t>::max();
    for (int j = 0; j < m; ++j) {
      const int d = j >= s ? j - s : j - s + m;
      if (diag[d] < best) {
        best = diag[d];
        bestJ = j;
      }
    }
    r.successor[k] = bestJ;
    r.score[k] = ToCm2(best);
  }
}

MatchResult FastFixed(const Fixed& p, const Fixed& c, int half) {
  MatchResult r;
  r.successor.resize(p.size());
  r.score.resize(p.size());
  FastRange(p, c, half, 0, p.size(), r);
  return r;
}

// exact squared distance (quantum^2) from every point of p to its nearest point of c, through a
// uniform grid over c searched in growing rings of cells
std::vector<int64_t> NearestSquared(const Fixed& p, const Fixed& c) {
  const int n = p.size();
  const int m = c.size();
  std::vector<int64_t> out(n, std::numeric_limits<int64_t>::max());
  if (m == 0) return out;
  int64_t minX = c.x[0], maxX = c.x[0], minY = c.y[0], maxY = c.y[0];
  double perimeter = 0.0;
  for (int j = 0; j < m; ++j) {
    minX = std::min(minX, c.x[j]);
    maxX = std::max(maxX, c.x[j]);
    minY = std::min(minY, c.y[j]);
    maxY = std::max(maxY, c.y[j]);
    const int next = j + 1 < m ? j + 1 : 0;
    perimeter += std::hypot(static_cast<double>(c.x[next] - c.x[j]),
                            static_cast<double>(c.y[next] - c.y[j]));
  }
  // cells about two point spacings wide, at most kGridCells along a side
  int64_t cell = std::max<int64_t>(1, static_cast<int64_t>(2.0 * perimeter / m));
  cell = std::max(cell, std::max(maxX - minX, maxY - minY) / kGridCells + 1);
  const int nx = static_cast<int>((maxX - minX) / cell) + 1;
  const int ny = static_cast<int>((maxY - minY) / cell) + 1;
  std::vector<int> start(static_cast<size_t>(nx) * ny + 1, 0);
  std::vector<int> items(m);
  auto cellOf = [&](int64_t x, int64_t y, int* cx, int* cy) {
    *cx = static_cast<int>(std::clamp<int64_t>((x - minX) / cell, 0, nx - 1));
    *cy = static_cast<int>(std::clamp<int64_t>((y - minY) / cell, 0, ny - 1));
  };
  // counting sort of the current points into their cells
  for (int j = 0; j < m; ++j) {
    int cx = 0, cy = 0;
    cellOf(c.x[j], c.y[j], &cx, &cy);
    ++start[static_cast<size_t>(cy) * nx + cx + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int j = 0; j < m; ++j) {
    int cx = 0, cy = 0;
    cellOf(c.x[j], c.y[j], &cx, &cy);
    items[fill[static_cast<size_t>(cy) * nx + cx]++] = j;
  }

  for (int k = 0; k < n; ++k) {
    int qx = 0, qy = 0;
    cellOf(p.x[k], p.y[k], &qx, &qy);
    int64_t best = std::numeric_limits<int64_t>::max();
    for (int r = 0; r <= std::max(nx, ny); ++r) {
      // the cells exactly r rings out
      for (int cy = std::max(qy - r, 0); cy <= std::min(qy + r, ny - 1); ++cy) {
        const bool edgeRow = cy == qy - r || cy == qy + r;
        const int step = edgeRow ? 1 : 2 * r;
        for (int cx = qx - r; cx <= qx + r; cx += std::max(step, 1)) {
          if (cx < 0 || cx >= nx) continue;
          const size_t id = static_cast<size_t>(cy) * nx + cx;
          for (int t = start[id]; t < start[id + 1]; ++t)
            best = std::min(best, Dist2(p, k, c, items[t]));
        }
      }
      // every cell further out lies at least r cells away
      const int64_t reach = r * cell;
      if (best <= reach * reach) break;
    }
    out[k] = best;
  }
  return out;
}

// window sums of per-point values over i = -half..half, cyclic
std::vector<int64_t> WindowBounds(const std::vector<int64_t>& v, int half) {
  const int n = static_cast<int>(v.size());
  std::vector<int64_t> out(n, 0);
  if (n == 0) return out;
  int64_t s = 0;
  for (int i = -half; i <= half; ++i) s += v[WrapIndex(i, n)];
  for (int k = 0; k < n; ++k) {
    out[k] = s;
    s += v[WrapIndex(k + half + 1, n)] - v[WrapIndex(k - half, n)];
  }
  return out;
}

}  // namespace

MatchResult MatchReference(const Contour& prev, const Contour& cur, int window) {
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  const int half = HalfWindow(window);
  if (m == 0) return EmptyCurrent(n);
  const Fixed p = ToFixed(prev);
  const Fixed c = ToFixed(cur);
  MatchResult r;
  r.successor.resize(n);
  r.score.resize(n);
  // every previous point against every current point, every window term computed afresh
  for (int k = 0; k < n; ++k) {
    int bestJ = -1;
    int64_t best = std::numeric_limits<int64_t>::max();
    for (int j = 0; j < m; ++j) {
      int64_t s = 0;
      for (int i = -half; i <= half; ++i) {
        s += Dist2(p, WrapIndex(k + i, n), c, WrapIndex(j + i, m));
      }
      if (s < best) {
        best = s;
        bestJ = j;
      }
    }
    r.successor[k] = bestJ;
    r.score[k] = ToCm2(best);
  }
  return r;
}

MatchResult MatchFast(const Contour& prev, const Contour& cur, int window) {
  const int half = HalfWindow(window);
  if (cur.cols() == 0) return EmptyCurrent(static_cast<int>(prev.cols()));
  return FastFixed(ToFixed(prev), ToFixed(cur), half);
}

MatchResult MatchWindowed(const Contour& prev, const Contour& cur, int window,
                          std::span<const int> predicted, int radius, double fallbackScore,
                          bool* fellBack) {
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  const int half = HalfWindow(window);
  const int terms = 2 * half + 1;
  assert(static_cast<int>(predicted.size()) == n && "one prediction per previous point");
  if (fellBack) *fellBack = false;
  if (m == 0) return EmptyCurrent(n);
  const Fixed p = ToFixed(prev);
  const Fixed c = ToFixed(cur);

  // a window as wide as the contour is the full search
  radius = std::max(radius, 0);
  const int width = 2 * radius + 1;
  if (BandSpansContour(radius, m) || static_cast<int>(predicted.size()) != n) {
    MatchResult r = FastFixed(p, c, half);
    r.fallbacks = n;
    if (fellBack) *fellBack = n > 0;
    return r;
  }

  // a lower bound on every point's score: no window can beat each of its previous points sitting
  // on its nearest current point; a band answer within `margin` of that bound is within `margin`
  // of the full search's answer
  const std::vector<int64_t> bound = WindowBounds(NearestSquared(p, c), half);
  const double perTerm = std::isfinite(fallbackScore) ? std::clamp(fallbackScore, 0.0, 1e4) : 0.0;
  const auto margin =
      static_cast<int64_t>(std::llround(perTerm / (kMatchQuantum * kMatchQuantum) * terms));
  MatchResult r;
  r.successor.resize(n);
  r.score.resize(n);
  std::vector<int> fallback;
  std::vector<int64_t> sums(width);

  for (int k0 = 0; k0 < n; k0 += kSegmentLength) {
    const int k1 = std::min(k0 + kSegmentLength, n);
    // the run follows the diagonal through its middle point's prediction; band t covers
    // j = k + diag - radius + t
    const int mid = (k0 + k1 - 1) / 2;
    const int diag = WrapIndex(predicted[mid] - mid, m);

    // direct sums for the run's first point
    for (int t = 0; t < width; ++t) {
      sums[t] = WindowSum(p, c, k0, WrapIndex(k0 + diag - radius + t, m), half);
    }

    for (int k = k0; k < k1; ++k) {
      // slide each band diagonal one step: the term k-1-half leaves, k+half enters
      if (k > k0) {
        const int aOut = WrapNear(k - 1 - half, n);
        const int aIn = WrapNear(k + half, n);
        int bOut = WrapNear(k - 1 - half + diag - radius, m);
        int bIn = WrapNear(k + half + diag - radius, m);
        for (int t = 0; t < width; ++t) {
          sums[t] += Dist2(p, aIn, c, bIn) - Dist2(p, aOut, c, bOut);
          if (++bOut == m) bOut = 0;
          if (++bIn == m) bIn = 0;
        }
      }
      // the best in the band, ties to the lowest j as in the full search
      const int jFirst = WrapNear(k + diag - radius, m);
      int bestT = 0;
      int bestJ = jFirst;
      for (int t = 1; t < width; ++t) {
        const int j = jFirst + t < m ? jFirst + t : jFirst + t - m;
        if (sums[t] < sums[bestT] || (sums[t] == sums[bestT] && j < bestJ)) {
          bestT = t;
          bestJ = j;
        }
      }
      // the answer is doubtful when the score still falls toward an edge of the band, or when
      // it lies more than the margin above the lower bound (a better answer may lie elsewhere):
      // the full search answers those points
      const int64_t best = sums[bestT];
      const bool atEdge = sums[0] == best || sums[width - 1] == best;
      if (atEdge || best > bound[k] + margin) fallback.push_back(k);
      r.successor[k] = bestJ;
      r.score[k] = ToCm2(best);
    }
  }

  // the full search answers the doubtful points, a run of neighbours at a time: a run costs
  // M (n + its length), so runs closer than n points are merged
  r.fallbacks = static_cast<int>(fallback.size());
  if (fellBack) *fellBack = !fallback.empty();
  for (size_t i = 0; i < fallback.size();) {
    size_t e = i + 1;
    while (e < fallback.size() && fallback[e] - fallback[e - 1] <= terms) ++e;
    FastRange(p, c, half, fallback[i], fallback[e - 1] + 1, r);
    i = e;
  }
  return r;
}

MatchResult MatchWindowed(const Contour& prev, const Contour& cur, int window, int predictedOffset,
                          int radius, double fallbackScore, bool* fellBack) {
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  std::vector<int> predicted(n, 0);
  if (m > 0) {
    for (int k = 0; k < n; ++k) {
      const auto scaled = static_cast<int>(std::lround(static_cast<double>(k) * m / n));
      predicted[k] = WrapIndex(predictedOffset + scaled, m);
    }
  }
  return MatchWindowed(prev, cur, window, predicted, radius, fallbackScore, fellBack);
}

namespace {

// principal axis angle of the points about their mean, and the axis ratio (>= 1)
void PrincipalAxis(const Contour& c, const Vec2& mean, double* angle, double* ratio) {
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int i = 0; i < c.cols(); ++i) {
    const Vec2 d = c.col(i) - mean;
    cov += d * d.transpose();
  }
  *angle = 0.5 * std::atan2(2.0 * cov(0, 1), cov(0, 0) - cov(1, 1));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const double lo = std::max(eig.eigenvalues()(0), 0.0);
  const double hi = std::max(eig.eigenvalues()(1), 0.0);
  *ratio = lo > 0.0 ? std::sqrt(hi / lo) : std::numeric_limits<double>::infinity();
}

}  // namespace

std::vector<int> PredictSuccessors(const Contour& prev, const Contour& cur) {
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  std::vector<int> predicted(n, -1);
  if (n == 0 || m == 0) return predicted;

  // rigid motion: centroid displacement, and the principal axis turn of an elongated shape
  // (taken modulo half a turn, the smaller way round)
  const Vec2 cPrev = prev.rowwise().mean();
  const Vec2 cCur = cur.rowwise().mean();
  double aPrev = 0.0, rPrev = 1.0, aCur = 0.0, rCur = 1.0;
  PrincipalAxis(prev, cPrev, &aPrev, &rPrev);
  PrincipalAxis(cur, cCur, &aCur, &rCur);
  double turn = 0.0;
  if (rPrev > kElongation && rCur > kElongation) {
    turn = std::remainder(aCur - aPrev, kPi);
  }
  const double cs = std::cos(turn);
  const double sn = std::sin(turn);
  auto moved = [&](int k) -> Vec2 {
    const Vec2 d = prev.col(k) - cPrev;
    return Vec2(cs * d.x() - sn * d.y(), sn * d.x() + cs * d.y()) + cCur;
  };
  auto dist2 = [&](const Vec2& q, int j) { return (cur.col(j) - q).squaredNorm(); };

  // the first point by a full scan
  {
    const Vec2 q = moved(0);
    int best = 0;
    for (int j = 1; j < m; ++j) {
      if (dist2(q, j) < dist2(q, best)) best = j;
    }
    predicted[0] = best;
  }
  // the others by descent from where the last one landed, advanced by the length ratio M/N
  const double step = static_cast<double>(m) / n;
  double carry = 0.0;
  int last = predicted[0];
  for (int k = 1; k < n; ++k) {
    carry += step;
    const int advance = static_cast<int>(carry);
    carry -= advance;
    const Vec2 q = moved(k);
    const int start = WrapNear(last + advance, m);
    int best = start;
    double bestD = dist2(q, best);
    for (int t = -kDescentReach; t <= kDescentReach; ++t) {
      const int j = WrapNear(start + t, m);
      const double d = dist2(q, j);
      if (d < bestD) {
        best = j;
        bestD = d;
      }
    }
    for (bool moving = true; moving;) {
      moving = false;
      for (const int j : {WrapNear(best - 1, m), WrapNear(best + 1, m)}) {
        const double d = dist2(q, j);
        if (d < bestD) {
          best = j;
          bestD = d;
          moving = true;
        }
      }
    }
    predicted[k] = best;
    last = best;
  }
  return predicted;
}

namespace {

// point-to-line alignment iterations of EstimateMotion, and when it stops early: cm and rad
constexpr int kAlignIterations = 8;
constexpr double kAlignConverged = 1e-5;
// a point farther off the current contour than this multiple of the median distance (and at
// least kAlignMinCut) is weighted down in proportion: a local shape change does not pull the fit
constexpr double kAlignCutFactor = 3.0;
constexpr double kAlignMinCut = 0.05;
// the turn counts as observable when the outline is elongated (kElongation), or when its
// rotational stiffness (sum of (n . perp(r))^2) is at least this fraction of its polar moment
// (sum of |r|^2). Measured through the synthetic camera: sensed fingertip circles reach 0.07 from
// their pixel noise (11 points) and 0.04 (25 points), a 2 x 1.4 cm ellipse 0.04 to 0.16, flat
// hands 0.30 to 0.33
constexpr double kTurnObservable = 0.15;
// a contact's own turn is followed when its axis ratio is above this on both frames. Measured
// through the synthetic camera: sensed round fingertips stay below 1.01, a 2 x 1.4 cm ellipse
// senses at 1.29 to 1.32 (at kElongation it lost its turn in 8 of 59 frames and its particles
// slid by a quarter of its turn along it), so the bar sits well between the two
constexpr double kTurnElongation = 1.15;

// Nearest point of a closed polyline to q: segment i (from point i to i + 1) and the parameter t
// along it. Vertex descent from `hint` (or a full scan when hint < 0), then the two segments at
// the nearest vertex.
struct Foot {
  int segment = 0;
  double t = 0.0;
  Vec2 point = Vec2::Zero();
};

Foot NearestFoot(const Contour& c, const Vec2& q, int hint, int* vertex) {
  const int m = static_cast<int>(c.cols());
  auto d2 = [&](int j) { return (c.col(j) - q).squaredNorm(); };
  int best = 0;
  if (hint < 0) {
    for (int j = 1; j < m; ++j) {
      if (d2(j) < d2(best)) best = j;
    }
  } else {
    best = WrapNear(hint, m);
    double bestD = d2(best);
    for (int t = -kDescentReach; t <= kDescentReach; ++t) {
      const int j = WrapNear(best + t, m);
      if (d2(j) < bestD) {
        bestD = d2(j);
        best = j;
      }
    }
    for (bool moving = true; moving;) {
      moving = false;
      for (const int j : {WrapNear(best - 1, m), WrapNear(best + 1, m)}) {
        if (d2(j) < bestD) {
          bestD = d2(j);
          best = j;
          moving = true;
        }
      }
    }
  }
  *vertex = best;
  Foot foot;
  foot.segment = best;
  foot.point = c.col(best);
  double bestD = std::numeric_limits<double>::infinity();
  for (const int i : {WrapNear(best - 1, m), best}) {
    const Vec2 a = c.col(i);
    const Vec2 b = c.col(WrapNear(i + 1, m));
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Vec2 f = a + t * ab;
    const double d = (q - f).squaredNorm();
    if (d < bestD) {
      bestD = d;
      foot.segment = i;
      foot.t = t;
      foot.point = f;
    }
  }
  return foot;
}

// (kFootRecheck mean spacings of c)^2, from its perimeter (0 for fewer than 2 points)
double FootRecheck2(const Contour& c, double perimeter) {
  const int m = static_cast<int>(c.cols());
  if (m < 2) return 0.0;
  const double reach = kFootRecheck * perimeter / m;
  return reach * reach;
}

// the feet of every point of q on c, each search starting where the last point's ended,
// advanced by the length ratio. `recheck2` is FootRecheck2(c, its perimeter): the caller works it
// out once for the several calls on the same c.
std::vector<Foot> Feet(const Contour& c, const Contour& q, double recheck2) {
  const int n = static_cast<int>(q.cols());
  const int m = static_cast<int>(c.cols());
  std::vector<Foot> feet(n);
  const double step = static_cast<double>(m) / std::max(n, 1);
  // A walk that fell behind or ahead where c gained or lost points in one place (a hand sliding
  // off the table's edge gains a run of points along it) can settle on a neighbouring finger, a
  // finger's width away. A foot farther than kFootRecheck spacings of c is searched again over
  // the whole of c, and the walk goes on from there.
  double carry = 0.0;
  int vertex = -1;
  for (int k = 0; k < n; ++k) {
    int hint = -1;
    if (k > 0) {
      carry += step;
      const int advance = static_cast<int>(carry);
      carry -= advance;
      hint = vertex + advance;
    }
    feet[k] = NearestFoot(c, q.col(k), hint, &vertex);
    if (hint >= 0 && (feet[k].point - q.col(k)).squaredNorm() > recheck2) {
      int whole = -1;
      const Foot global = NearestFoot(c, q.col(k), -1, &whole);
      if ((global.point - q.col(k)).squaredNorm() < (feet[k].point - q.col(k)).squaredNorm()) {
        feet[k] = global;
        vertex = whole;
      }
    }
  }
  return feet;
}

Vec2 MeanOf(const Contour& c) {
  return c.rowwise().mean();
}

}  // namespace

Contour Transformed(const Contour& prev, const Pose2& motion) {
  Contour out(2, prev.cols());
  const double cs = std::cos(motion.angle);
  const double sn = std::sin(motion.angle);
  for (Eigen::Index k = 0; k < prev.cols(); ++k) {
    const Vec2 p = prev.col(k);
    out.col(k) = Vec2(cs * p.x() - sn * p.y(), sn * p.x() + cs * p.y()) + motion.pos;
  }
  return out;
}

namespace {

// How Align treats the turn: found by the fit, decided on the first iteration from what the
// outline shows (EstimateMotion), or held at its seed (a piece of an outline)
enum class TurnRule { kDecide, kHeld };

// Point-to-line alignment of prev against cur from the motion q = R(theta) (p - cPrev) + cPrev +
// shift: each moved point against the nearest segment of cur, points far off the contour
// weighted down, so that a local shape change does not pull the fit. Refines theta (unless held)
// and shift; with TurnRule::kDecide, *observable says whether the outline shows its turning (when
// it does not, the turn is held at 0). Returns the RMS distance of the moved points to cur.
double Align(const Contour& prev, const Contour& cur, const Vec2& cPrev, TurnRule rule,
             bool elongated, double* theta, Vec2* shift, bool* observable) {
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  bool turnLocked = rule == TurnRule::kHeld;
  const double recheck2 = FootRecheck2(cur, Perimeter(cur));
  std::vector<double> dist(n);
  Contour q(2, n);
  for (int it = 0; it < kAlignIterations; ++it) {
    const double cs = std::cos(*theta);
    const double sn = std::sin(*theta);
    const Vec2 centre = cPrev + *shift;
    for (int k = 0; k < n; ++k) {
      const Vec2 d = prev.col(k) - cPrev;
      q.col(k) = Vec2(cs * d.x() - sn * d.y(), sn * d.x() + cs * d.y()) + centre;
    }
    const std::vector<Foot> feet = Feet(cur, q, recheck2);
    for (int k = 0; k < n; ++k) dist[k] = (q.col(k) - feet[k].point).norm();
    std::vector<double> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    const double cut = std::max(kAlignMinCut, kAlignCutFactor * sorted[n / 2]);

    // normal equations of sum w (n . (q + dtheta perp(q - centre) + dt - foot))^2
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    double polar = 0.0;
    for (int k = 0; k < n; ++k) {
      const Foot& f = feet[k];
      const Vec2 s0 = cur.col(f.segment);
      const Vec2 s1 = cur.col(WrapNear(f.segment + 1, m));
      Vec2 tangent = s1 - s0;
      const double len = tangent.norm();
      if (len <= 0.0) continue;
      tangent /= len;
      const Vec2 normal(tangent.y(), -tangent.x());
      const Vec2 rel = q.col(k) - centre;
      const double w = dist[k] <= cut ? 1.0 : cut / dist[k];
      const Eigen::Vector3d j(normal.dot(Vec2(-rel.y(), rel.x())), normal.x(), normal.y());
      const double e = normal.dot(q.col(k) - f.point);
      a += w * j * j.transpose();
      b -= w * e * j;
      polar += w * rel.squaredNorm();
    }
    if (it == 0 && rule == TurnRule::kDecide) {
      *observable = elongated || (polar > 0.0 && a(0, 0) >= kTurnObservable * polar);
      if (!*observable) {
        // a round outline shows no turn: it translates
        turnLocked = true;
        *theta = 0.0;
      }
    }
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    if (turnLocked) {
      const Eigen::Matrix2d at = a.bottomRightCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
      x.tail<2>() = at.ldlt().solve(b.tail<2>());
    } else {
      x = (a + 1e-9 * Eigen::Matrix3d::Identity()).ldlt().solve(b);
    }
    if (!x.allFinite()) break;
    *theta += x(0);
    *shift += Vec2(x(1), x(2));
    if (std::abs(x(0)) < kAlignConverged && x.tail<2>().norm() < kAlignConverged) break;
  }

  // the final residual, at the final motion
  const Pose2 motion{cPrev + *shift - Rotate(cPrev, *theta), *theta};
  const Contour moved = Transformed(prev, motion);
  const std::vector<Foot> feet = Feet(cur, moved, recheck2);
  double sum = 0.0;
  for (int k = 0; k < n; ++k) sum += (moved.col(k) - feet[k].point).squaredNorm();
  return std::sqrt(sum / n);
}

}  // namespace

ContourMotion EstimateMotion(const Contour& prev, const Contour& cur) {
  ContourMotion r;
  const int n = static_cast<int>(prev.cols());
  const int m = static_cast<int>(cur.cols());
  if (n == 0 || m == 0 || !prev.allFinite() || !cur.allFinite()) return r;
  const Vec2 cPrev = MeanOf(prev);
  const Vec2 cCur = MeanOf(cur);
  if (m < 3 || n < 3) {
    r.motion.pos = cCur - cPrev;
    return r;
  }

  // seed: the centroid shift, and the principal axis turn of an elongated outline (modulo half a
  // turn, the smaller way round)
  double aPrev = 0.0, rPrev = 1.0, aCur = 0.0, rCur = 1.0;
  PrincipalAxis(prev, cPrev, &aPrev, &rPrev);
  PrincipalAxis(cur, cCur, &aCur, &rCur);
  double theta = 0.0;
  const bool elongated = rPrev > kTurnElongation && rCur > kTurnElongation;
  if (elongated) theta = std::remainder(aCur - aPrev, kPi);
  Vec2 shift = cCur - cPrev;  // q = R(theta) (p - cPrev) + cPrev + shift
  r.residual =
      Align(prev, cur, cPrev, TurnRule::kDecide, elongated, &theta, &shift, &r.turnObservable);
  r.motion.angle = theta;
  r.motion.pos = cPrev + shift - Rotate(cPrev, theta);
  return r;
}

Pose2 EstimatePieceMotion(const Contour& piece, const Contour& cur, const Pose2& seed) {
  const int n = static_cast<int>(piece.cols());
  if (n < 3 || cur.cols() < 3 || !piece.allFinite() || !cur.allFinite()) return seed;
  // the seed as a turn about the piece's mean and a shift of that mean
  const Vec2 cPrev = MeanOf(piece);
  double theta = seed.angle;
  Vec2 shift = seed.Apply(cPrev) - cPrev;
  bool observable = false;
  Align(piece, cur, cPrev, TurnRule::kHeld, false, &theta, &shift, &observable);
  return Pose2{cPrev + shift - Rotate(cPrev, theta), theta};
}

Contour ResampleInPhase(const Contour& cur, const Contour& reference, int count) {
  const int m = static_cast<int>(cur.cols());
  const int n = static_cast<int>(reference.cols());
  if (m < 2 || count < 1) return cur;
  // arc length at each point of cur
  std::vector<double> arc(m + 1, 0.0);
  for (int j = 0; j < m; ++j)
    arc[j + 1] = arc[j] + (cur.col(WrapNear(j + 1, m)) - cur.col(j)).norm();
  const double total = arc[m];
  if (!(total > 0.0) || !std::isfinite(total)) return cur;

  // the phase: where reference point k projects, less where its k-th share of the perimeter lies
  double phase = 0.0;
  if (n > 0 && reference.allFinite()) {
    // the perimeter is the arc length summed in the same order
    const std::vector<Foot> feet = Feet(cur, reference, FootRecheck2(cur, total));
    const double refStep = total / n;
    std::vector<double> offsets(n);
    double first = 0.0;
    for (int k = 0; k < n; ++k) {
      const Foot& f = feet[k];
      const double at = arc[f.segment] + f.t * (arc[f.segment + 1] - arc[f.segment]);
      const double offset = at - k * refStep;
      if (k == 0) first = offset;
      // offsets are taken about the first one, so a phase near the contour's start does not split
      offsets[k] = std::remainder(offset - first, total);
    }
    std::nth_element(offsets.begin(), offsets.begin() + n / 2, offsets.end());
    phase = first + offsets[n / 2];
  }

  Contour out(2, count);
  const double step = total / count;
  for (int k = 0; k < count; ++k) {
    double s = std::fmod(phase + k * step, total);
    if (s < 0.0) s += total;
    // the segment holding arc length s (arc is increasing)
    const int j = std::clamp(
        static_cast<int>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin()) - 1, 0, m - 1);
    const double len = arc[j + 1] - arc[j];
    const double t = len > 0.0 ? std::clamp((s - arc[j]) / len, 0.0, 1.0) : 0.0;
    out.col(k) = cur.col(j) + t * (cur.col(WrapNear(j + 1, m)) - cur.col(j));
  }
  return out;
}

std::vector<int> Predecessors(const MatchResult& match, int currentCount) {
  std::vector<int> pred(std::max(currentCount, 0), -1);
  for (int k = 0; k < static_cast<int>(match.successor.size()); ++k) {
    const int j = match.successor[k];
    if (j < 0 || j >= currentCount) continue;
    // strict comparison keeps the lowest k on equal scores
    if (pred[j] < 0 || match.score[k] < match.score[pred[j]]) pred[j] = k;
  }
  return pred;
}

}  // namespace pg
