// A scene of axis-aligned boxes answering the proxies stage's SceneQuery, for tests.
#pragma once

#include "proxygrasp/proxies/types.h"

#include <algorithm>
#include <vector>

namespace pg::testing {

/// An axis-aligned box on the table: footprint [lo, hi], top at `top` cm.
struct Box {
  Vec2 lo;
  Vec2 hi;
  double top = 0.0;
};

/// Boxes on the table. Footprints of different boxes are expected not to overlap.
class BoxScene : public SceneQuery {
 public:
  std::vector<Box> boxes;

  double TopHeightAt(const Vec2& p) const override {
    double top = 0.0;
    for (const Box& b : boxes) {
      if (Inside(b, p)) top = std::max(top, b.top);
    }
    return top;
  }

  double FootprintDepth(const Vec2& p, double* topHeight) const override {
    const Box* highest = nullptr;
    for (const Box& b : boxes) {
      if (Inside(b, p) && (!highest || b.top > highest->top)) highest = &b;
    }
    if (topHeight) *topHeight = highest ? highest->top : 0.0;
    if (!highest) return 0.0;
    return std::min({p.x() - highest->lo.x(), highest->hi.x() - p.x(), p.y() - highest->lo.y(),
                     highest->hi.y() - p.y()});
  }

  Vec2 NearestOutside(const Vec2& p) const override {
    for (const Box& b : boxes) {
      if (!Inside(b, p)) continue;
      // leave through the nearest side, a hair beyond it
      const double eps = 1e-6;
      const double dl = p.x() - b.lo.x(), dr = b.hi.x() - p.x();
      const double dd = p.y() - b.lo.y(), du = b.hi.y() - p.y();
      const double m = std::min({dl, dr, dd, du});
      if (m == dl) return Vec2(b.lo.x() - eps, p.y());
      if (m == dr) return Vec2(b.hi.x() + eps, p.y());
      if (m == dd) return Vec2(p.x(), b.lo.y() - eps);
      return Vec2(p.x(), b.hi.y() + eps);
    }
    return p;
  }

  ObjectId ObjectAt(const Vec2& p) const override {
    ObjectId best = kNoObject;
    for (size_t i = 0; i < boxes.size(); ++i) {
      if (Inside(boxes[i], p) && (best == kNoObject || boxes[i].top > boxes[best].top)) {
        best = static_cast<ObjectId>(i);
      }
    }
    return best;
  }

  static bool Inside(const Box& b, const Vec2& p) {
    return p.x() > b.lo.x() && p.x() < b.hi.x() && p.y() > b.lo.y() && p.y() < b.hi.y();
  }
};

}  // namespace pg::testing
