#include "proxygrasp/app/hand_input.h"

#include <algorithm>
#include <cmath>

namespace pg {

void MouseHands::Move(const Vec2& table, bool rotate) {
  // with the modifier a pinch turns in place with the horizontal motion
  if (m_right && rotate) {
    m_angle += (table.x() - m_cursor.x()) * m_params.dragRotate;
  } else {
    m_pinchCenter += table - m_cursor;
  }
  m_cursor = table;
}

void MouseHands::Press(Button button, const Vec2& table, bool flat) {
  m_cursor = table;
  m_pinchCenter = table;
  m_flat = flat;
  if (button == Button::kLeft) m_left = true;
  if (button == Button::kRight) m_right = true;
}

void MouseHands::Release(Button button) {
  if (button == Button::kLeft) m_left = false;
  if (button == Button::kRight) m_right = false;
}

void MouseHands::Wheel(double notches, bool rotate) {
  if (rotate) {
    m_angle += notches * m_params.rotateStep;
    return;
  }
  m_opening = std::clamp(m_opening + notches * m_params.wheelStep, m_params.minOpening,
                         m_params.maxOpening);
}

void MouseHands::Clear() {
  m_left = false;
  m_right = false;
}

std::vector<ContactShape> MouseHands::Shapes() const {
  std::vector<ContactShape> shapes;
  if (!m_left && !m_right) return shapes;
  ContactShape finger;
  finger.kind = ShapeKind::kCircle;
  finger.radius = m_params.fingerRadius;

  // Shift: one flat hand, fingers along the pinch axis turned a quarter
  if (m_flat) {
    ContactShape hand;
    hand.kind = ShapeKind::kHandFlat;
    hand.scale = m_params.handScale;
    hand.pose = {m_right ? m_pinchCenter : m_cursor, m_angle};
    shapes.push_back(hand);
    return shapes;
  }
  if (m_right) {
    // two fingertips at +-opening/2 along the pinch axis about its centre
    const Vec2 half = 0.5 * m_opening * Vec2(std::cos(m_angle), std::sin(m_angle));
    finger.pose.pos = m_pinchCenter - half;
    shapes.push_back(finger);
    finger.pose.pos = m_pinchCenter + half;
    shapes.push_back(finger);
  }
  if (m_left && !m_right) {
    finger.pose.pos = m_cursor;
    shapes.push_back(finger);
  }
  return shapes;
}

std::vector<ContactShape> TouchHands::Shapes() const {
  std::vector<ContactShape> shapes;
  for (const auto& [finger, pos] : m_fingers) {
    ContactShape tip;
    tip.kind = ShapeKind::kCircle;
    tip.radius = m_radius;
    tip.pose.pos = pos;
    shapes.push_back(tip);
  }
  return shapes;
}

}  // namespace pg
