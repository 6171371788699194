// Hands emulated with a mouse or a touch screen, as contact shapes for the synthetic table camera,
// so the whole pipeline runs for them. Platform-free: the app feeds it pointer events already
// mapped into table cm.
#pragma once

#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/types.h"

#include <cstdint>
#include <map>
#include <vector>

namespace pg {

/// Settings of the mouse hands.
struct MouseHandParams {
  double fingerRadius = 0.8;  ///< fingertip radius, cm
  double opening = 8.0;       ///< starting distance between the pinch's fingertip centres, cm
  double minOpening = 1.6;    ///< closest the pinch closes, cm
  double maxOpening = 40.0;   ///< widest the pinch opens, cm
  double wheelStep = 0.5;     ///< opening change per wheel notch, cm
  double rotateStep = DegToRad(5.0);  ///< pinch turn per wheel notch with the modifier, rad
  double dragRotate = 0.1;  ///< pinch turn per cm of horizontal drag with the modifier, rad/cm
  double handScale = 0.9;   ///< flat hand size, non-dimensional
};

/// The mouse as hands: left drag moves one fingertip; right drag is a two-finger pinch around the
/// cursor whose opening the wheel changes; the rotate modifier (Ctrl with the wheel, Alt while
/// dragging) turns the pinch; Shift gives a flat hand instead.
class MouseHands {
 public:
  explicit MouseHands(const MouseHandParams& params = {})
      : m_params(params), m_opening(params.opening) {}

  /// Buttons of the mouse.
  enum class Button { kLeft, kRight };

  /// The cursor moved to a table point, cm. With `rotate` held during a right drag the pinch turns
  /// with the horizontal motion and stays where it is.
  void Move(const Vec2& table, bool rotate = false);
  /// A button went down at a table point; `flat` (Shift) makes the contact a flat hand.
  void Press(Button button, const Vec2& table, bool flat);
  /// A button went up.
  void Release(Button button);
  /// The wheel turned by `notches` (positive away from the user opens the pinch); with `rotate`
  /// it turns the pinch instead.
  void Wheel(double notches, bool rotate);
  /// Lifts everything (the window lost focus, the level restarted).
  void Clear();

  /// The contact shapes on the table now.
  std::vector<ContactShape> Shapes() const;

  double opening() const { return m_opening; }
  double angle() const { return m_angle; }
  const Vec2& cursor() const { return m_cursor; }

 private:
  MouseHandParams m_params;
  Vec2 m_cursor = Vec2::Zero();
  Vec2 m_pinchCenter = Vec2::Zero();
  bool m_left = false;
  bool m_right = false;
  bool m_flat = false;
  double m_opening;
  double m_angle = 0.0;  // the pinch's axis, rad
};

/// Touch-screen fingers as fingertips: one circle per finger down.
class TouchHands {
 public:
  explicit TouchHands(double fingerRadius = 0.8) : m_radius(fingerRadius) {}
  /// A finger touched down or moved to a table point, cm.
  void Move(int64_t finger, const Vec2& table) { m_fingers[finger] = table; }
  /// A finger lifted.
  void Lift(int64_t finger) { m_fingers.erase(finger); }
  /// Lifts every finger.
  void Clear() { m_fingers.clear(); }
  /// One fingertip per finger down, in finger id order.
  std::vector<ContactShape> Shapes() const;

 private:
  double m_radius;
  std::map<int64_t, Vec2> m_fingers;
};

}  // namespace pg
