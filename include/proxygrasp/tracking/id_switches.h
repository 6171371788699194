// Id switches, measured from the tracker's output alone: how often one finger held on the table
// gets a new id. Used to judge the sensing and tracking settings on recorded footage (issue 14),
// where no ground truth of which finger is which exists.
#pragma once

#include "proxygrasp/tracking/types.h"

#include <cstdint>
#include <vector>

namespace pg {

/// What counts as an id switch. Two ways one finger is seen to get a new id:
/// - a flicker: a contact lifts and, within maxGapFrames frames, a new contact starts within
///   maxDistance of where it lifted (the blob dropped out for a frame or two);
/// - a jump: in one frame as many contacts lift as new ones start, each new one within maxJump
///   of a lifted one (the fingers moved farther than the tracker's reach in one frame).
struct IdSwitchParams {
  /// Farthest a flicker's new contact may start from where the lifted one was last seen, cm.
  /// One fingertip's width (contacts are about 1.5 cm across): another finger landing this
  /// close within a few frames of the first lifting is unlikely, so it is the same finger.
  double maxDistance = 1.5;
  /// Most frames a lifted contact may stay away and come back as a flicker, counted from the
  /// frame that lists it as lifted (0: the new contact starts in that same frame). 3 frames is
  /// 100-150 ms at 20-30 fps: long enough for a blob that drops below min_area or the threshold
  /// for a frame or two, shorter than lifting a fingertip and putting it down again on purpose.
  int maxGapFrames = 3;
  /// Farthest a jump's new contact may be from the lifted one, cm: a hand's span. Farther, in one
  /// frame, is not the same finger (2 m/s at 20 fps).
  double maxJump = 10.0;
};

/// How an id switch was seen.
enum class IdSwitchKind { kFlicker, kJump };
inline constexpr const char* kIdSwitchKindNames[] = {"flicker", "jump"};

/// One id switch: where and how the new id continued a lifted contact.
struct IdSwitch {
  IdSwitchKind kind = IdSwitchKind::kFlicker;
  int64_t frame = 0;         ///< the frame the new id started
  ContactId lifted = kNoId;  ///< the id that lifted
  ContactId next = kNoId;    ///< the new id
  int gapFrames = 0;         ///< frames from the lift to the new id (0: the same frame)
  double distance = 0.0;     ///< from the lifted contact's last centroid to the new one, cm
  double liftedArea = 0.0;   ///< the lifted contact's last area, cm^2
};

/// The running count of a clip.
struct IdSwitchCount {
  int switches = 0;           ///< new ids that continued a lifted contact, both kinds
  int jumps = 0;              ///< of which jumps
  int64_t contactFrames = 0;  ///< sum over frames of the contacts on the table (lifted excluded)
  int64_t frames = 0;         ///< contact sets counted

  /// Minutes of touch at `fps` frames per second: contactFrames / fps / 60.
  double MinutesOfTouch(double fps) const;
  /// Switches per minute of touch at `fps`; 0 when nothing touched.
  double PerMinuteOfTouch(double fps) const;
};

/// Counts id switches over a sequence of the tracker's contact sets, one frame at a time.
class IdSwitchCounter {
 public:
  explicit IdSwitchCounter(const IdSwitchParams& params = IdSwitchParams()) : m_params(params) {}

  /// Adds the next frame's contact set (frames in order, none skipped).
  void Add(const ContactSet& set);

  const IdSwitchCount& count() const { return m_count; }
  /// Every switch counted, in order (to see why they happen).
  const std::vector<IdSwitch>& switches() const { return m_switches; }

 private:
  struct Lift {
    Vec2 at;        // last centroid, cm
    int64_t frame;  // the frame that listed it as lifted, less the frames it was kept (missed)
    ContactId id;
    double area;  // cm^2
  };

  void Count(IdSwitchKind kind, const Lift& lift, const Contact& next, int64_t frame);

  IdSwitchParams m_params;
  IdSwitchCount m_count;
  std::vector<IdSwitch> m_switches;
  std::vector<Lift> m_lifts;  // lifted within the last maxGapFrames frames, not yet continued
};

}  // namespace pg
