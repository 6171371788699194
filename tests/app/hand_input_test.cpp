// Mouse and touch hands turn pointer events (in table cm) into contact shapes.
#include "proxygrasp/app/hand_input.h"

#include "proxygrasp/core/units.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pg {
namespace {

// positions are sums and products of exact decimal steps: round-off only
constexpr double kExact = 1e-9;

TEST(MouseHands, NothingTouchesUntilAButtonIsDown) {
  MouseHands hands;
  hands.Move({10, 10});
  EXPECT_TRUE(hands.Shapes().empty());
}

TEST(MouseHands, LeftDragMovesOneFingertip) {
  MouseHandParams params;
  params.fingerRadius = 0.7;
  MouseHands hands(params);
  hands.Press(MouseHands::Button::kLeft, {10, 12}, false);
  hands.Move({13, 16});
  const std::vector<ContactShape> shapes = hands.Shapes();
  ASSERT_EQ(shapes.size(), 1u);
  EXPECT_EQ(shapes[0].kind, ShapeKind::kCircle);
  EXPECT_DOUBLE_EQ(shapes[0].radius, 0.7);
  EXPECT_NEAR(shapes[0].pose.pos.x(), 13, kExact);
  EXPECT_NEAR(shapes[0].pose.pos.y(), 16, kExact);
  hands.Release(MouseHands::Button::kLeft);
  EXPECT_TRUE(hands.Shapes().empty());
}

TEST(MouseHands, RightDragPinchesAroundTheCursor) {
  MouseHands hands;  // opening 8 cm, 0.5 cm per notch
  hands.Press(MouseHands::Button::kRight, {30, 23}, false);
  std::vector<ContactShape> shapes = hands.Shapes();
  ASSERT_EQ(shapes.size(), 2u);
  EXPECT_NEAR(shapes[0].pose.pos.x(), 26, kExact);
  EXPECT_NEAR(shapes[1].pose.pos.x(), 34, kExact);
  EXPECT_NEAR(shapes[0].pose.pos.y(), 23, kExact);

  // two notches towards the user close it by 1 cm
  hands.Wheel(-2, false);
  EXPECT_NEAR(hands.opening(), 7.0, kExact);
  shapes = hands.Shapes();
  EXPECT_NEAR(shapes[1].pose.pos.x() - shapes[0].pose.pos.x(), 7.0, kExact);

  // the pinch follows the cursor
  hands.Move({35, 25});
  shapes = hands.Shapes();
  EXPECT_NEAR(0.5 * (shapes[0].pose.pos.x() + shapes[1].pose.pos.x()), 35, kExact);
  EXPECT_NEAR(shapes[0].pose.pos.y(), 25, kExact);

  // it never closes past its minimum
  hands.Wheel(-100, false);
  EXPECT_NEAR(hands.opening(), MouseHandParams{}.minOpening, kExact);
}

TEST(MouseHands, TheModifierTurnsThePinch) {
  MouseHands hands;
  hands.Press(MouseHands::Button::kRight, {30, 23}, false);
  // 18 notches of 5 degrees: a quarter turn, the fingers now one above the other
  hands.Wheel(18, true);
  EXPECT_NEAR(hands.angle(), DegToRad(90), 1e-6);
  std::vector<ContactShape> shapes = hands.Shapes();
  EXPECT_NEAR(shapes[0].pose.pos.x(), 30, 1e-5);
  EXPECT_NEAR(shapes[0].pose.pos.y(), 19, 1e-5);
  EXPECT_NEAR(shapes[1].pose.pos.y(), 27, 1e-5);
  EXPECT_NEAR(hands.opening(), 8.0, kExact);

  // dragging with the modifier turns it in place: 0.1 rad per cm
  hands.Move({35, 23}, true);
  EXPECT_NEAR(hands.angle(), DegToRad(90) + 0.5, 1e-6);
  shapes = hands.Shapes();
  EXPECT_NEAR(0.5 * (shapes[0].pose.pos.x() + shapes[1].pose.pos.x()), 30, 1e-6);
}

TEST(MouseHands, ShiftGivesAFlatHand) {
  MouseHands hands;
  hands.Press(MouseHands::Button::kLeft, {20, 20}, true);
  const std::vector<ContactShape> shapes = hands.Shapes();
  ASSERT_EQ(shapes.size(), 1u);
  EXPECT_EQ(shapes[0].kind, ShapeKind::kHandFlat);
  EXPECT_NEAR(shapes[0].pose.pos.x(), 20, kExact);
  hands.Clear();
  EXPECT_TRUE(hands.Shapes().empty());
}

TEST(TouchHands, OneFingertipPerFinger) {
  TouchHands touch(0.9);
  touch.Move(7, {10, 10});
  touch.Move(3, {20, 15});
  touch.Move(7, {11, 10});
  std::vector<ContactShape> shapes = touch.Shapes();
  ASSERT_EQ(shapes.size(), 2u);
  // in finger id order
  EXPECT_NEAR(shapes[0].pose.pos.x(), 20, kExact);
  EXPECT_NEAR(shapes[1].pose.pos.x(), 11, kExact);
  EXPECT_DOUBLE_EQ(shapes[1].radius, 0.9);
  touch.Lift(3);
  EXPECT_EQ(touch.Shapes().size(), 1u);
}

}  // namespace
}  // namespace pg
