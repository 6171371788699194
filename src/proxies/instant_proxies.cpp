#include "proxygrasp/proxies/instant_proxies.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pg {
namespace {

// pyramid levels of the Lucas-Kanade flow: motion up to ~window * 2^levels / 2 pixels is found
constexpr int kFlowLevels = 3;
// a particle is tagged with a contact when a contour point lies within this many spacings
constexpr double kTagReach = 2.0;

Vec2 PixelCentre(const TableImage& image, double u, double v) {
  return image.origin + Vec2(u + 0.5, v + 0.5) * image.cmPerPixel;
}

bool SameGrid(const TableImage& a, const TableImage& b) {
  return a.image.size() == b.image.size() && a.image.type() == b.image.type() &&
         a.cmPerPixel == b.cmPerPixel && a.origin == b.origin;
}

// the current contact and contour point nearest p within reach, or (kNoId, -1)
void NearestContactPoint(const ContactSet& contacts, const Vec2& p, double reach,
                         ContactId* contact, int* index) {
  *contact = kNoId;
  *index = -1;
  double best = reach * reach;
  for (const Contact& c : contacts.contacts) {
    if (c.state == ContactState::kLifted || c.blob.contour.cols() == 0) continue;
    const Contour& contour = c.blob.contour;
    // skip contacts whose bounding box is out of reach
    const Vec2 lo = contour.rowwise().minCoeff();
    const Vec2 hi = contour.rowwise().maxCoeff();
    if ((p.array() < lo.array() - reach).any() || (p.array() > hi.array() + reach).any()) continue;
    for (int j = 0; j < contour.cols(); ++j) {
      const double d2 = (contour.col(j) - p).squaredNorm();
      if (d2 < best) {
        best = d2;
        *contact = c.id;
        *index = j;
      }
    }
  }
}

}  // namespace

std::vector<EdgePixel> EdgePixels(const TableImage& image, double threshold, double spacing) {
  std::vector<EdgePixel> out;
  if (image.image.empty() || image.cmPerPixel <= 0.0) return out;
  cv::Mat grey;
  if (image.image.type() == CV_8UC1) {
    grey = image.image;
  } else {
    image.image.convertTo(grey, CV_8U);
  }

  // gradient magnitude in grey levels per pixel: the 3x3 Sobel weighs a unit ramp by 8
  cv::Mat gx, gy, magnitude;
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::magnitude(gx, gy, magnitude);

  // the strongest pixel above the threshold in each grid cell
  const int cell = std::max(1, static_cast<int>(std::lround(spacing / image.cmPerPixel)));
  for (int v0 = 0; v0 < magnitude.rows; v0 += cell) {
    for (int u0 = 0; u0 < magnitude.cols; u0 += cell) {
      float best = static_cast<float>(threshold);
      cv::Point at(-1, -1);
      for (int v = v0; v < std::min(v0 + cell, magnitude.rows); ++v) {
        const float* row = magnitude.ptr<float>(v);
        for (int u = u0; u < std::min(u0 + cell, magnitude.cols); ++u) {
          if (row[u] > best) {
            best = row[u];
            at = cv::Point(u, v);
          }
        }
      }
      if (at.x < 0) continue;
      out.push_back({at, PixelCentre(image, at.x, at.y), static_cast<double>(best)});
    }
  }
  return out;
}

std::vector<Vec2> ImageMotion(const TableImage& previous, const TableImage& current,
                              const std::vector<EdgePixel>& points, int window) {
  std::vector<Vec2> motion(points.size(), Vec2::Zero());
  if (points.empty() || previous.image.empty() || !SameGrid(previous, current) ||
      current.image.type() != CV_8UC1) {
    return motion;
  }
  // track each point from the current image back into the previous one
  std::vector<cv::Point2f> from(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    from[i] =
        cv::Point2f(static_cast<float>(points[i].pixel.x), static_cast<float>(points[i].pixel.y));
  }
  std::vector<cv::Point2f> back;
  std::vector<unsigned char> status;
  std::vector<float> error;
  const int w = std::max(window, 5);
  cv::calcOpticalFlowPyrLK(current.image, previous.image, from, back, status, error, cv::Size(w, w),
                           kFlowLevels);
  // the motion into this frame is the reverse of that track, in table cm
  for (size_t i = 0; i < points.size(); ++i) {
    if (!status[i] || !std::isfinite(back[i].x) || !std::isfinite(back[i].y)) continue;
    motion[i] = Vec2(from[i].x - back[i].x, from[i].y - back[i].y) * current.cmPerPixel;
  }
  return motion;
}

void InstantProxies::Update(const ProxyParams& params, const ContactSet& contacts,
                            const SceneQuery& scene, const TableImage& image, IdCounter& ids,
                            ParticlePlan& plan) {
  // last frame's particles all end
  PlanDeletions(plan);
  m_live.clear();

  // a particle at every strong edge pixel, moved by the optical flow there
  const std::vector<EdgePixel> edges =
      EdgePixels(image, params.instantThreshold, params.instantSpacing);
  const std::vector<Vec2> motion = ImageMotion(m_previous, image, edges, params.instantFlowWindow);
  const double reach = kTagReach * params.instantSpacing;
  for (size_t i = 0; i < edges.size(); ++i) {
    PlannedParticle p;
    p.id = ids.Next();
    p.action = ParticleAction::kCreated;
    NearestContactPoint(contacts, edges[i].pos, reach, &p.contact, &p.index);
    // instant particles have no heights of their own: every placement but ground raycasts
    if (params.placement != Placement::kGround) {
      p.start = edges[i].pos;
      p.baseHeight = scene.TopHeightAt(p.start);
    } else {
      p.start = scene.NearestOutside(edges[i].pos);
      p.baseHeight = 0.0;
    }
    p.target = p.start + motion[i];
    plan.particles.push_back(p);
    m_live.push_back({p.id, p.contact, p.target, p.baseHeight});
  }

  // keep this frame's image for the next frame's flow
  m_previous.image = image.image.clone();
  m_previous.cmPerPixel = image.cmPerPixel;
  m_previous.origin = image.origin;
}

void InstantProxies::PlanDeletions(ParticlePlan& plan) const {
  for (const Live& l : m_live) {
    PlannedParticle p;
    p.id = l.id;
    p.contact = l.contact;
    p.action = ParticleAction::kDeleted;
    p.target = l.target;
    p.baseHeight = l.baseHeight;
    plan.particles.push_back(p);
  }
}

void InstantProxies::DeleteAll(ParticlePlan& plan) {
  PlanDeletions(plan);
  Reset();
}

void InstantProxies::Reset() {
  m_live.clear();
  m_previous = TableImage{};
}

}  // namespace pg
