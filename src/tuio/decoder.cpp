#include "proxygrasp/tuio/decoder.h"

#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string_view>

namespace pg {

namespace {

// a frame id this far below the last one means the sender restarted, not a reordered datagram
constexpr int64_t kRestartGap = 100;
// a blob or bounds ellipse is never thinner than this, cm, so its polygon keeps an area
constexpr double kMinSemiAxis = 0.05;

// shape precedence within one TUIO 2.0 frame: an outline beats bounds beats a pointer
int Precedence(TuioShape kind) {
  switch (kind) {
    case TuioShape::kContour:
      return 3;
    case TuioShape::kBounds:
    case TuioShape::kBlob:
      return 2;
    default:
      return 1;
  }
}

// the polygon without repeated neighbours (the closing edge included), wound counter-clockwise
void CleanPolygon(std::vector<Vec2>& points) {
  std::vector<Vec2> kept;
  kept.reserve(points.size());
  for (const Vec2& p : points)
    if (kept.empty() || (p - kept.back()).squaredNorm() > 1e-18) kept.push_back(p);
  while (kept.size() > 1 && (kept.front() - kept.back()).squaredNorm() <= 1e-18) kept.pop_back();
  double area2 = 0.0;
  for (size_t i = 0; i < kept.size(); ++i) area2 += Cross(kept[i], kept[(i + 1) % kept.size()]);
  if (area2 < 0.0) std::reverse(kept.begin(), kept.end());
  points = std::move(kept);
}

}  // namespace

uint64_t TuioStats::TotalDropped() const {
  uint64_t total = 0;
  for (uint64_t n : dropped) total += n;
  return total;
}

std::string TuioStats::Summary() const {
  const uint64_t total = TotalDropped();
  if (total == 0) return "";
  std::string out = std::to_string(total) + " dropped:";
  const char* separator = " ";
  for (size_t r = 0; r < dropped.size(); ++r) {
    if (dropped[r] == 0) continue;
    out += separator + std::to_string(dropped[r]) + " " + kTuioDropNames[r];
    separator = ", ";
  }
  return out;
}

TuioDecoder::TuioDecoder(const TuioParams& params) : m_params(params) {
  std::fill(std::begin(m_lastFrame), std::end(m_lastFrame), int64_t(-1));
}

void TuioDecoder::Decode(std::span<const OscMessage> messages, double now) {
  ++m_stats.packets;
  m_lastPacket = now;
  m_anyPacket = true;
  m_now = now;
  for (const OscMessage& m : messages) {
    ++m_stats.messages;
    const std::string_view address = m.address;
    if (address.starts_with("/tuio2/")) {
      DecodeTuio2(m);
    } else if (address == "/tuio/2Dcur") {
      DecodeTuio11(kCursor11, m);
    } else if (address == "/tuio/2Dblb") {
      DecodeTuio11(kBlob11, m);
    } else if (address.starts_with("/tuio/")) {
      ++m_stats.ignored;  // 2Dobj, 25Dcur, 3Dcur, custom profiles: not contacts here
    } else {
      ++m_stats[TuioDrop::kUnknownAddress];
    }
  }
}

bool TuioDecoder::CheckCoord(double v) {
  if (!std::isfinite(v)) {
    ++m_stats[TuioDrop::kNonFinite];
    return false;
  }
  if (v < -m_params.margin || v > 1.0 + m_params.margin) {
    ++m_stats[TuioDrop::kOutOfRange];
    return false;
  }
  return true;
}

Vec2 TuioDecoder::ToTable(double u, double v) const {
  const double y = m_params.flipY ? 1.0 - v : v;
  return Vec2(u * m_params.table.width, y * m_params.table.height);
}

std::vector<Vec2> TuioDecoder::Ellipse(Vec2 centre, double rx, double ry, double angle) const {
  const int n = std::max(3, m_params.circlePoints);
  std::vector<Vec2> points;
  points.reserve(n);
  const double c = std::cos(angle), s = std::sin(angle);
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * kPi * k / n;
    const Vec2 local(rx * std::cos(t), ry * std::sin(t));
    points.push_back(centre + Vec2(c * local.x() - s * local.y(), s * local.x() + c * local.y()));
  }
  return points;
}

bool TuioDecoder::ReadAlive(const OscMessage& m, size_t first, std::vector<TuioSessionId>& ids) {
  ids.clear();
  for (size_t k = first; k < m.args.size(); ++k) {
    if (!m.args[k].IsInt()) {
      ++m_stats[TuioDrop::kWrongType];
      ids.clear();
      return false;
    }
  }
  std::set<TuioSessionId> seen;
  for (size_t k = first; k < m.args.size(); ++k) {
    if (!seen.insert(m.args[k].i).second) continue;
    if (static_cast<int>(ids.size()) >= m_params.maxContacts) {
      ++m_stats[TuioDrop::kTooManyContacts];
      break;
    }
    ids.push_back(m.args[k].i);
  }
  return true;
}

void TuioDecoder::AddShape(Pending& p, TuioSessionId id, Shape shape) {
  auto it = p.shapes.find(id);
  if (it == p.shapes.end()) {
    if (static_cast<int>(p.shapes.size()) >= m_params.maxContacts) {
      ++m_stats[TuioDrop::kTooManyContacts];
      return;
    }
    p.shapes.emplace(id, std::move(shape));
  } else if (Precedence(shape.kind) >= Precedence(it->second.kind)) {
    it->second = std::move(shape);
  }
}

bool TuioDecoder::AcceptFrameId(Profile profile, int64_t frame) const {
  if (frame == -1 || !m_haveLastFrame[profile]) return true;
  const int64_t last = m_lastFrame[profile];
  return frame > last || last - frame > kRestartGap;
}

void TuioDecoder::DecodeTuio2(const OscMessage& m) {
  const std::string_view address = std::string_view(m.address).substr(7);
  const std::vector<OscArg>& a = m.args;
  Pending& p = m_pending[kTuio2];
  const bool isShape = address == "ocg" || address == "ptr" || address == "p3d" || address == "bnd";

  if (address == "frm") {
    // frm f_id [time dim source]
    if (!StartsWithInt(a)) return;
    // the same frame id again continues a frame split over several bundles
    if (p.open && p.frame == a[0].i) return;
    if (p.open) ++m_stats[TuioDrop::kIncompleteFrame];
    p = Pending();
    p.open = true;
    p.frame = a[0].i;
    p.late = !AcceptFrameId(kTuio2, p.frame);
    return;
  }
  if (!isShape && address != "alv") {
    ++m_stats.ignored;  // tok, sym, icg, skg, ...: nothing this decoder turns into a contact
    return;
  }
  // a valid shape or alv without a frm opens a frame with no id
  const auto openImplicitly = [&p] {
    if (p.open) return;
    p = Pending();
    p.open = true;
  };

  if (address == "alv") {
    std::vector<TuioSessionId> alive;
    if (!ReadAlive(m, 0, alive)) return;
    openImplicitly();
    p.alive = std::move(alive);
    p.haveAlive = true;
    Complete(kTuio2);
    return;
  }

  // every shape starts with the session id
  if (!StartsWithInt(a)) return;
  const TuioSessionId id = a[0].i;
  Shape shape;
  if (address == "ocg") {
    // ocg s_id x0 y0 x1 y1 ...: the outline, closed implicitly
    const size_t coords = a.size() - 1;
    if (coords % 2 != 0 || coords < 6) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
    if (coords / 2 > static_cast<size_t>(std::max(3, m_params.maxContourPoints))) {
      ++m_stats[TuioDrop::kTooManyPoints];
      return;
    }
    for (size_t k = 1; k < a.size(); ++k) {
      if (!a[k].IsFloat()) {
        ++m_stats[TuioDrop::kWrongType];
        return;
      }
    }
    for (size_t k = 1; k < a.size(); ++k)
      if (!CheckCoord(a[k].f)) return;
    shape.kind = TuioShape::kContour;
    shape.contour.reserve(coords / 2);
    for (size_t k = 1; k + 1 < a.size(); k += 2)
      shape.contour.push_back(ToTable(a[k].f, a[k + 1].f));
    CleanPolygon(shape.contour);
    if (shape.contour.size() < 3) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
  } else if (address == "p3d") {
    // p3d s_id tu_id c_id x y z [x_ax y_ax z_ax radius ...]: a fingertip at a height, z in units
    // of the table's width
    if (a.size() < 6) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
    if (!a[1].IsInt() || !a[2].IsInt() || !a[3].IsFloat() || !a[4].IsFloat() || !a[5].IsFloat()) {
      ++m_stats[TuioDrop::kWrongType];
      return;
    }
    if (!CheckCoord(a[3].f) || !CheckCoord(a[4].f) || !CheckCoord(a[5].f)) return;
    shape.kind = TuioShape::kPointer;
    shape.contour =
        Ellipse(ToTable(a[3].f, a[4].f), m_params.cursorRadius, m_params.cursorRadius, 0.0);
    openImplicitly();
    if (!p.late) {
      p.heights[id] = a[5].f * m_params.table.width;
      AddShape(p, id, std::move(shape));
    }
    return;
  } else if (address == "ptr") {
    // ptr s_id tu_id c_id x y [angle shear radius press ...]: a fingertip
    if (a.size() < 5) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
    if (!a[1].IsInt() || !a[2].IsInt() || !a[3].IsFloat() || !a[4].IsFloat()) {
      ++m_stats[TuioDrop::kWrongType];
      return;
    }
    if (!CheckCoord(a[3].f) || !CheckCoord(a[4].f)) return;
    shape.kind = TuioShape::kPointer;
    shape.contour =
        Ellipse(ToTable(a[3].f, a[4].f), m_params.cursorRadius, m_params.cursorRadius, 0.0);
  } else {
    // bnd s_id x y angle width height [area]: the ellipse inscribed in the oriented box
    if (a.size() < 6) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
    for (size_t k = 1; k < 6; ++k) {
      if (!a[k].IsFloat()) {
        ++m_stats[TuioDrop::kWrongType];
        return;
      }
    }
    if (!std::isfinite(a[3].f)) {
      ++m_stats[TuioDrop::kNonFinite];
      return;
    }
    if (!CheckCoord(a[1].f) || !CheckCoord(a[2].f) || !CheckCoord(a[4].f) || !CheckCoord(a[5].f))
      return;
    shape.kind = TuioShape::kBounds;
    const double angle = m_params.flipY ? -a[3].f : a[3].f;
    shape.contour =
        Ellipse(ToTable(a[1].f, a[2].f),
                std::max(kMinSemiAxis, 0.5 * std::abs(a[4].f) * m_params.table.width),
                std::max(kMinSemiAxis, 0.5 * std::abs(a[5].f) * m_params.table.height), angle);
  }
  openImplicitly();
  if (!p.late) AddShape(p, id, std::move(shape));
}

bool TuioDecoder::ReadSet11(Profile profile, const OscMessage& m) {
  const std::vector<OscArg>& a = m.args;
  // 2Dcur: set s x y [X Y m]; 2Dblb: set s x y a w h [f X Y A m r]; trailing extras are allowed
  const size_t needed = profile == kCursor11 ? 4 : 7;
  if (a.size() < needed) {
    ++m_stats[TuioDrop::kTooFewArgs];
    return false;
  }
  if (!a[1].IsInt()) {
    ++m_stats[TuioDrop::kWrongType];
    return false;
  }
  for (size_t k = 2; k < needed; ++k) {
    if (!a[k].IsFloat()) {
      ++m_stats[TuioDrop::kWrongType];
      return false;
    }
  }
  if (!CheckCoord(a[2].f) || !CheckCoord(a[3].f)) return false;
  Shape shape;
  const Vec2 centre = ToTable(a[2].f, a[3].f);
  if (profile == kCursor11) {
    shape.kind = TuioShape::kCursor;
    shape.contour = Ellipse(centre, m_params.cursorRadius, m_params.cursorRadius, 0.0);
  } else {
    if (!std::isfinite(a[4].f)) {
      ++m_stats[TuioDrop::kNonFinite];
      return false;
    }
    if (!CheckCoord(a[5].f) || !CheckCoord(a[6].f)) return false;
    shape.kind = TuioShape::kBlob;
    const double angle = m_params.flipY ? -a[4].f : a[4].f;
    shape.contour =
        Ellipse(centre, std::max(kMinSemiAxis, 0.5 * std::abs(a[5].f) * m_params.table.width),
                std::max(kMinSemiAxis, 0.5 * std::abs(a[6].f) * m_params.table.height), angle);
  }
  AddShape(m_pending[profile], a[1].i, std::move(shape));
  return true;
}

bool TuioDecoder::StartsWithInt(const std::vector<OscArg>& a) {
  if (a.empty()) {
    ++m_stats[TuioDrop::kTooFewArgs];
    return false;
  }
  if (!a[0].IsInt()) {
    ++m_stats[TuioDrop::kWrongType];
    return false;
  }
  return true;
}

void TuioDecoder::DecodeTuio11(Profile profile, const OscMessage& m) {
  const std::vector<OscArg>& a = m.args;
  if (a.empty()) {
    ++m_stats[TuioDrop::kTooFewArgs];
    return;
  }
  if (!a[0].IsString()) {
    ++m_stats[TuioDrop::kWrongType];
    return;
  }
  Pending& p = m_pending[profile];
  p.open = true;
  const std::string& command = a[0].s;
  if (command == "set") {
    ReadSet11(profile, m);
  } else if (command == "alive") {
    if (ReadAlive(m, 1, p.alive)) p.haveAlive = true;
  } else if (command == "fseq") {
    if (a.size() < 2) {
      ++m_stats[TuioDrop::kTooFewArgs];
      return;
    }
    if (!a[1].IsInt()) {
      ++m_stats[TuioDrop::kWrongType];
      return;
    }
    p.frame = a[1].i;
    p.late = !AcceptFrameId(profile, p.frame);
    Complete(profile);
  } else if (command == "source") {
    // the sender's name: nothing to do
  } else {
    ++m_stats[TuioDrop::kUnknownCommand];
  }
}

void TuioDecoder::Complete(Profile profile) {
  Pending p = std::move(m_pending[profile]);
  m_pending[profile] = Pending();
  if (p.late) {
    ++m_stats[TuioDrop::kLateFrame];
    return;
  }
  if (p.frame != -1) {
    m_lastFrame[profile] = p.frame;
    m_haveLastFrame[profile] = true;
  }
  // without an alive list the live set stays as it was, plus the sessions given a shape
  if (!p.haveAlive) {
    for (const auto& [id, track] : m_live)
      if (track.profile == profile) p.alive.push_back(id);
    for (const auto& [id, shape] : p.shapes) p.alive.push_back(id);
  }
  const std::set<TuioSessionId> alive(p.alive.begin(), p.alive.end());

  TuioFrame frame;
  frame.frame = p.frame;
  frame.time = m_now;

  // this profile's sessions missing from alive have lifted
  for (auto it = m_live.begin(); it != m_live.end();) {
    if (it->second.profile == profile && !alive.contains(it->first)) {
      frame.lifted.push_back(it->first);
      it = m_live.erase(it);
    } else {
      ++it;
    }
  }
  // live sessions with a new shape take it; new ones need one to become a contact
  for (TuioSessionId id : alive) {
    auto shape = p.shapes.find(id);
    auto track = m_live.find(id);
    if (shape == p.shapes.end()) continue;  // keeps its last shape, or waits for its first
    if (track == m_live.end()) {
      if (static_cast<int>(m_live.size()) >= m_params.maxContacts) {
        ++m_stats[TuioDrop::kTooManyContacts];
        continue;
      }
      track = m_live.emplace(id, Track()).first;
      track->second.isNew = true;
    }
    Track& t = track->second;
    t.profile = profile;
    t.kind = shape->second.kind;
    t.contour = std::move(shape->second.contour);
    t.centroid = PolygonCentroid(ToContour(t.contour));
    const auto height = p.heights.find(id);
    t.height = height == p.heights.end() ? std::nullopt : std::optional<double>(height->second);
  }

  // every live contact, of every profile
  frame.contacts.reserve(m_live.size());
  for (auto& [id, t] : m_live) {
    TuioContact c;
    c.id = id;
    c.isNew = t.isNew;
    c.shape = t.kind;
    c.contour = t.contour;
    c.centroid = t.centroid;
    c.height = t.height;
    frame.contacts.push_back(std::move(c));
    t.isNew = false;
  }
  ++m_stats.frames;
  Push(std::move(frame));
}

void TuioDecoder::Push(TuioFrame frame) {
  m_frames.push_back(std::move(frame));
  const size_t cap = static_cast<size_t>(std::max(2, m_params.maxQueuedFrames));
  if (m_frames.size() > cap) {
    // merge the oldest half into one frame, keeping the order
    const size_t half = m_frames.size() / 2;
    TuioFrame merged = MergeTuioFrames(std::span(m_frames.data(), half));
    m_frames.erase(m_frames.begin() + 1, m_frames.begin() + half);
    m_frames.front() = std::move(merged);
  }
}

bool TuioDecoder::Expire(double now) {
  if (!m_anyPacket || now - m_lastPacket <= m_params.timeout) return false;
  for (Pending& p : m_pending) p = Pending();
  std::fill(std::begin(m_haveLastFrame), std::end(m_haveLastFrame), false);
  if (m_live.empty()) return false;
  TuioFrame frame;
  frame.frame = -1;
  frame.time = now;
  for (const auto& [id, track] : m_live) frame.lifted.push_back(id);
  m_live.clear();
  ++m_stats.expired;
  Push(std::move(frame));
  return true;
}

std::vector<TuioFrame> TuioDecoder::TakeFrames() {
  std::vector<TuioFrame> frames = std::move(m_frames);
  m_frames.clear();
  return frames;
}

void TuioDecoder::Reset() {
  m_live.clear();
  for (Pending& p : m_pending) p = Pending();
  std::fill(std::begin(m_haveLastFrame), std::end(m_haveLastFrame), false);
  m_frames.clear();
  m_anyPacket = false;
}

TuioFrame MergeTuioFrames(std::span<const TuioFrame> frames) {
  TuioFrame merged;
  if (frames.empty()) return merged;
  merged.frame = frames.back().frame;
  merged.time = frames.back().time;
  merged.contacts = frames.back().contacts;
  // new in any merged frame: the caller has not seen it yet
  std::set<TuioSessionId> fresh, live;
  for (const TuioFrame& f : frames)
    for (const TuioContact& c : f.contacts)
      if (c.isNew) fresh.insert(c.id);
  for (TuioContact& c : merged.contacts) {
    if (fresh.contains(c.id)) c.isNew = true;
    live.insert(c.id);
  }
  std::set<TuioSessionId> lifted;
  for (const TuioFrame& f : frames)
    for (TuioSessionId id : f.lifted)
      if (!live.contains(id)) lifted.insert(id);
  merged.lifted.assign(lifted.begin(), lifted.end());
  return merged;
}

std::vector<TuioFrame> ReplayTuio(std::span<const OscBundle> bundles, const TuioParams& params,
                                  double interval) {
  TuioDecoder decoder(params);
  std::vector<TuioFrame> frames;
  for (size_t k = 0; k < bundles.size(); ++k) {
    decoder.Decode(bundles[k], static_cast<double>(k) * interval);
    for (TuioFrame& f : decoder.TakeFrames()) frames.push_back(std::move(f));
  }
  return frames;
}

std::vector<double> ReplayArrivals(std::span<const OscBundle> bundles, double interval) {
  std::vector<double> arrivals(bundles.size());
  bool timed = !bundles.empty();
  for (size_t k = 0; k < bundles.size() && timed; ++k) {
    const OscTimeTag& t = bundles[k].time;
    timed = !(t == OscTimeTag{0, 1});
    if (timed && k > 0) timed = t.ToSeconds() >= bundles[k - 1].time.ToSeconds();
  }
  for (size_t k = 0; k < bundles.size(); ++k)
    arrivals[k] = timed ? bundles[k].time.ToSeconds() - bundles.front().time.ToSeconds()
                        : static_cast<double>(k) * interval;
  return arrivals;
}

std::vector<TuioFrame> ReplayRecording(std::span<const OscBundle> bundles, const TuioParams& params,
                                       double interval, TuioStats* stats) {
  const std::vector<double> arrivals = ReplayArrivals(bundles, interval);
  TuioDecoder decoder(params);
  std::vector<TuioFrame> frames;
  auto take = [&] {
    for (TuioFrame& f : decoder.TakeFrames()) frames.push_back(std::move(f));
  };
  for (size_t k = 0; k < bundles.size(); ++k) {
    decoder.Decode(bundles[k], arrivals[k]);
    take();
  }
  // the stream ends: what is still live lifts once the timeout has passed, as it would live
  if (!arrivals.empty()) {
    decoder.Expire(arrivals.back() + params.timeout + interval);
    take();
  }
  if (stats) *stats = decoder.stats();
  return frames;
}

}  // namespace pg
