// A level: the public entry points (LoadLevel, ParseLevel) over the loader (loader.h), and what a
// loaded level answers itself (regions, goals, lookups by name).
#include "proxygrasp/level/level.h"

#include "loader.h"

#include "proxygrasp/core/units.h"

#include <cmath>

namespace pg {

bool Region::Contains(const Vec2& p) const {
  if (kind == Kind::kCircle) return (p - center).squaredNorm() <= radius * radius;
  return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
}

bool Goal::IsMet(const Pose2& pose) const {
  if (zone && !zone->Contains(pose.pos)) return false;
  if (angle && std::abs(WrapAngle(pose.angle - *angle)) > tolerance) return false;
  return true;
}

const ObjectSpec* Level::FindObject(std::string_view objectName) const {
  for (const ObjectSpec& o : objects) {
    if (o.name == objectName) return &o;
  }
  return nullptr;
}

const Variant* Level::FindVariant(std::string_view variantName) const {
  for (const Variant& v : variants) {
    if (v.name == variantName) return &v;
  }
  return nullptr;
}

Result<Level> LoadLevel(const std::string& path) {
  return levelfile::Loader().Load(path, std::nullopt);
}

Result<Level> ParseLevel(std::string_view text, const std::string& path) {
  return levelfile::Loader().Load(path, text);
}

}  // namespace pg
