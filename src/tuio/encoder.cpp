#include "proxygrasp/tuio/encoder.h"

#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>

namespace pg {

namespace {

// an outline is simplified this much more each time it does not fit a bundle
constexpr double kCoarsenFactor = 1.5;
constexpr int kHeaderBytes = 16;  // "#bundle\0" and the time tag

// bytes a message adds to a bundle: its size field and itself
size_t InBundle(const OscMessage& m) {
  return 4 + OscMessageSize(m);
}

// Douglas-Peucker over the open chain points[first..last] (indices modulo n), marking kept points
void SimplifyChain(std::span<const Vec2> points, int first, int last, double tolerance,
                   std::vector<char>& keep) {
  const int n = static_cast<int>(points.size());
  std::vector<std::pair<int, int>> stack{{first, last}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = -1.0;
    int worstIndex = -1;
    for (int k = a + 1; k < b; ++k) {
      const double d = DistanceToSegment(points[k % n], points[a % n], points[b % n]);
      if (d > worst) {
        worst = d;
        worstIndex = k;
      }
    }
    if (worstIndex < 0 || worst <= tolerance) continue;
    keep[worstIndex % n] = 1;
    stack.push_back({a, worstIndex});
    stack.push_back({worstIndex, b});
  }
}

}  // namespace

std::vector<Vec2> SimplifyClosed(std::span<const Vec2> points, double tolerance) {
  const int n = static_cast<int>(points.size());
  if (n <= 3) return {points.begin(), points.end()};
  // anchor the first point and the point farthest from it, then simplify both halves
  int far = 0;
  double farDistance = -1.0;
  for (int k = 1; k < n; ++k) {
    const double d = (points[k] - points[0]).squaredNorm();
    if (d > farDistance) {
      farDistance = d;
      far = k;
    }
  }
  std::vector<char> keep(n, 0);
  keep[0] = keep[far] = 1;
  SimplifyChain(points, 0, far, tolerance, keep);
  SimplifyChain(points, far, n, tolerance, keep);
  // a polygon needs a third point: the one farthest from the line through the other two
  if (std::count(keep.begin(), keep.end(), 1) < 3) {
    int third = -1;
    double best = -1.0;
    for (int k = 0; k < n; ++k) {
      if (keep[k]) continue;
      const double d = DistanceToSegment(points[k], points[0], points[far]);
      if (d > best) {
        best = d;
        third = k;
      }
    }
    if (third >= 0) keep[third] = 1;
  }
  std::vector<Vec2> out;
  for (int k = 0; k < n; ++k)
    if (keep[k]) out.push_back(points[k]);
  return out;
}

OrientedBox PrincipalBox(std::span<const Vec2> points) {
  OrientedBox box;
  if (points.empty()) return box;
  // principal axes of the points' covariance
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (const Vec2& p : points) {
    const Vec2 d = p - mean;
    sxx += d.x() * d.x();
    sxy += d.x() * d.y();
    syy += d.y() * d.y();
  }
  double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  if (angle < 0.0) angle += kPi;
  if (angle >= kPi) angle -= kPi;
  // extents along the axes
  const Vec2 u(std::cos(angle), std::sin(angle));
  const Vec2 v(-u.y(), u.x());
  double uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
  for (const Vec2& p : points) {
    const double pu = (p - mean).dot(u), pv = (p - mean).dot(v);
    uMin = std::min(uMin, pu);
    uMax = std::max(uMax, pu);
    vMin = std::min(vMin, pv);
    vMax = std::max(vMax, pv);
  }
  box.angle = angle;
  box.width = uMax - uMin;
  box.height = vMax - vMin;
  box.centre = mean + u * (0.5 * (uMin + uMax)) + v * (0.5 * (vMin + vMax));
  return box;
}

TuioEncoder::TuioEncoder(const TuioEncoderParams& params) : m_params(params) {}

float TuioEncoder::NormX(double x) const {
  return static_cast<float>(x / m_params.table.width);
}

float TuioEncoder::NormZ(double z) const {
  return static_cast<float>(z / m_params.table.width);
}

float TuioEncoder::NormY(double y) const {
  const double v = y / m_params.table.height;
  return static_cast<float>(m_params.flipY ? 1.0 - v : v);
}

std::vector<OscBundle> TuioEncoder::Encode(int64_t frame, OscTimeTag time,
                                           std::span<const TuioOutContact> contacts) {
  ++m_stats.frames;
  const TableParams& table = m_params.table;
  const size_t maxBytes = static_cast<size_t>(std::max(256, m_params.maxBundleBytes));

  OscMessage frm{"/tuio2/frm",
                 {OscArg::Int(static_cast<int32_t>(frame)), OscArg::Time(time),
                  OscArg::Int(static_cast<int32_t>(((m_params.sensorWidth & 0xffff) << 16) |
                                                   (m_params.sensorHeight & 0xffff))),
                  OscArg::String(m_params.source)}};
  const size_t fixed = kHeaderBytes + InBundle(frm);

  // the contacts that alv can name while leaving room for one contact (a pointer, bounds and a
  // triangle outline take under 200 bytes, a 3D pointer 72 more)
  const bool anyHeight = std::any_of(contacts.begin(), contacts.end(),
                                     [](const TuioOutContact& c) { return c.height.has_value(); });
  const size_t room = anyHeight ? 280 : 200;
  OscMessage alv{"/tuio2/alv", {}};
  std::vector<const TuioOutContact*> sent;
  for (const TuioOutContact& c : contacts) {
    if (c.contour.size() < 3) {
      ++m_stats.droppedContacts;
      continue;
    }
    alv.args.push_back(OscArg::Int(static_cast<int32_t>(c.id)));
    if (fixed + InBundle(alv) + room > maxBytes) {
      alv.args.pop_back();
      ++m_stats.droppedContacts;
      continue;
    }
    sent.push_back(&c);
  }
  // room for contacts in each bundle after its frm; alv goes at the end of the last one
  const size_t budget = maxBytes - fixed;

  std::vector<OscBundle> bundles;
  OscBundle current{time, {frm}};
  size_t used = 0;
  for (const TuioOutContact* c : sent) {
    const auto id = OscArg::Int(static_cast<int32_t>(c->id));
    // pointer at the centroid, with the radius of a disc of the same area
    const double area = std::abs(SignedArea(ToContour(c->contour)));
    OscMessage ptr{"/tuio2/ptr",
                   {id, OscArg::Int(0), OscArg::Int(0), OscArg::Float(NormX(c->centroid.x())),
                    OscArg::Float(NormY(c->centroid.y())), OscArg::Float(0.0f), OscArg::Float(0.0f),
                    OscArg::Float(static_cast<float>(std::sqrt(area / kPi) / table.width)),
                    OscArg::Float(1.0f)}};
    // bounds: the box along the outline's principal axes
    const OrientedBox box = PrincipalBox(c->contour);
    double angle = m_params.flipY ? -box.angle : box.angle;
    if (angle < 0.0) angle += 2.0 * kPi;
    OscMessage bnd{"/tuio2/bnd",
                   {id, OscArg::Float(NormX(box.centre.x())), OscArg::Float(NormY(box.centre.y())),
                    OscArg::Float(static_cast<float>(angle)),
                    OscArg::Float(static_cast<float>(box.width / table.width)),
                    OscArg::Float(static_cast<float>(box.height / table.height)),
                    OscArg::Float(static_cast<float>(area / (table.width * table.height)))}};
    // a depth camera's contact: the 3D pointer, its z the mean height above the table in units of
    // the table's width (as x), no pointing direction (0, 0, 0), the pointer's radius
    OscMessage p3d{"/tuio2/p3d", {}};
    if (c->height) {
      p3d.args = {id,
                  OscArg::Int(0),
                  OscArg::Int(0),
                  ptr.args[3],
                  ptr.args[4],
                  OscArg::Float(NormZ(*c->height)),
                  OscArg::Float(0.0f),
                  OscArg::Float(0.0f),
                  OscArg::Float(0.0f),
                  ptr.args[7]};
    }
    // the outline, simplified further until the messages fit one bundle
    const size_t pairSize = InBundle(ptr) + InBundle(bnd) + (c->height ? InBundle(p3d) : 0);
    double tolerance = m_params.tolerance;
    OscMessage ocg{"/tuio2/ocg", {}};
    for (int attempt = 0;; ++attempt) {
      const std::vector<Vec2> outline = SimplifyClosed(c->contour, tolerance);
      ocg.args.assign(1, id);
      for (const Vec2& p : outline) {
        ocg.args.push_back(OscArg::Float(NormX(p.x())));
        ocg.args.push_back(OscArg::Float(NormY(p.y())));
      }
      if (pairSize + InBundle(ocg) <= budget || outline.size() <= 3 || attempt > 60) break;
      tolerance *= kCoarsenFactor;
    }
    if (tolerance > m_params.tolerance) ++m_stats.coarsened;
    const size_t groupSize = pairSize + InBundle(ocg);
    // a contact that does not fit the open bundle starts the next one
    if (used > 0 && used + groupSize > budget) {
      bundles.push_back(std::move(current));
      current = OscBundle{time, {frm}};
      used = 0;
    }
    current.messages.push_back(std::move(ptr));
    current.messages.push_back(std::move(bnd));
    current.messages.push_back(std::move(ocg));
    if (c->height) current.messages.push_back(std::move(p3d));
    used += groupSize;
  }
  if (used + InBundle(alv) > budget) {
    bundles.push_back(std::move(current));
    current = OscBundle{time, {frm}};
  }
  current.messages.push_back(std::move(alv));
  bundles.push_back(std::move(current));
  if (m_params.cursors11) bundles.push_back(EncodeCursors11(frame, time, contacts));
  m_stats.bundles += bundles.size();
  return bundles;
}

OscBundle TuioEncoder::EncodeCursors11(int64_t frame, OscTimeTag time,
                                       std::span<const TuioOutContact> contacts) {
  const size_t maxBytes = static_cast<size_t>(std::max(256, m_params.maxBundleBytes));
  const double now = time.ToSeconds();
  OscMessage source{"/tuio/2Dcur", {OscArg::String("source"), OscArg::String(m_params.source)}};
  OscMessage alive{"/tuio/2Dcur", {OscArg::String("alive")}};
  OscMessage fseq{"/tuio/2Dcur",
                  {OscArg::String("fseq"), OscArg::Int(static_cast<int32_t>(frame))}};
  std::vector<OscMessage> sets;
  size_t setsSize = 0;
  std::map<TuioSessionId, std::pair<Vec2, double>> cursors;
  for (const TuioOutContact& c : contacts) {
    // set s x y X Y m, velocity in normalised units per second from the last frame
    const float x = NormX(c.centroid.x()), y = NormY(c.centroid.y());
    float vx = 0.0f, vy = 0.0f;
    if (auto last = m_lastCursor.find(c.id); last != m_lastCursor.end()) {
      const double dt = now - last->second.second;
      if (dt > 1e-6 && dt < 1.0) {
        vx = static_cast<float>((x - NormX(last->second.first.x())) / dt);
        vy = static_cast<float>((y - NormY(last->second.first.y())) / dt);
      }
    }
    OscMessage set{
        "/tuio/2Dcur",
        {OscArg::String("set"), OscArg::Int(static_cast<int32_t>(c.id)), OscArg::Float(x),
         OscArg::Float(y), OscArg::Float(vx), OscArg::Float(vy), OscArg::Float(0.0f)}};
    // the bundle with this cursor in alive and its set added must still fit
    alive.args.push_back(OscArg::Int(static_cast<int32_t>(c.id)));
    const size_t withCursor = setsSize + InBundle(set) + kHeaderBytes + InBundle(source) +
                              InBundle(alive) + InBundle(fseq);
    if (withCursor > maxBytes) {
      alive.args.pop_back();
      ++m_stats.droppedCursors;
      continue;
    }
    setsSize += InBundle(set);
    sets.push_back(std::move(set));
    cursors[c.id] = {c.centroid, now};
  }
  m_lastCursor = std::move(cursors);
  OscBundle bundle{time, {std::move(source), std::move(alive)}};
  for (OscMessage& s : sets) bundle.messages.push_back(std::move(s));
  bundle.messages.push_back(std::move(fseq));
  return bundle;
}

}  // namespace pg
