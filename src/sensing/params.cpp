#include "proxygrasp/sensing/types.h"

namespace pg {

void Describe(SyntheticCameraParams& p, ParamVisitor& v) {
  VisitEnum(v, "kind", p.kind, kCameraKindNames,
            {"what the camera is: \"ir\" sees the table from below (8-bit frames), \"depth\" is a "
             "Kinect v1-like depth camera above it (16-bit frames, mm)",
             Apply::kRestart});
  v.Integer("width", p.width, 64, 4096, "px", {"image width", Apply::kRestart});
  v.Integer("height", p.height, 48, 4096, "px", {"image height", Apply::kRestart});
  v.Real("background", p.background, 0, 255, "grey", "mean background level");
  v.Real("contact_level", p.contactLevel, 0, 255, "grey", "level of full contact");
  v.Real("halo_level", p.haloLevel, 0, 255, "grey", "extra brightness of a hovering hand's halo");
  v.Real("halo_width", p.haloWidth, 0, 20, "cm", "how far the halo reaches beyond a hand");
  v.Real("vignetting", p.vignetting, 0, 1, "1", "background brightness lost at the corners");
  v.Real("gradient", p.gradient, -128, 128, "grey", "slow left-to-right background ramp");
  v.Real("noise", p.noise, 0, 64, "grey", "Gaussian sensor noise deviation");
  v.Real("distortion", p.distortion, -1, 1, "1",
         {"radial lens distortion k1 (0 = none)", Apply::kRestart});
  v.Real("perspective", p.perspective, 0, 0.3, "1",
         {"camera-to-table keystone as a fraction of the width (0 = none)", Apply::kRestart});
  v.Integer("seed", p.seed, 0, 2147483647, "1",
            {"noise seed; the same seed gives the same frames", Apply::kRestart});
  // the depth camera's own keys (kind = "depth"); the IR camera ignores them
  v.Real("camera_height", p.cameraHeight, 0, 1000, "cm",
         {"depth: the camera's height above the table, looking straight down at its centre; 0 "
          "derives it from the table's size and a Kinect v1's field of view and nearest range "
          "(docs/sensing.md)",
          Apply::kRestart});
  v.Real("projector_baseline", p.projectorBaseline, -50, 50, "cm",
         "depth: the IR projector's offset from the camera along the image's x (+: toward the "
         "table's right edge); what a raised body hides from it reads 0 (0 = no shadow)");
  v.Real("disparity_noise", p.disparityNoise, 0, 10, "raw steps",
         "depth: per-pixel noise deviation in Kinect raw disparity steps (0.5 is 1.45 mm at 1 m, "
         "growing with the distance squared)");
  v.Boolean("disparity_steps", p.disparitySteps,
            "depth: round each reading to Kinect v1's 11-bit disparity steps (2.9 mm at 1 m)");
  v.Real("edge_holes", p.edgeHoles, 0, 1, "1",
         "depth: chance that a pixel at a depth edge (edge_jump) reads 0");
  v.Real("edge_jump", p.edgeJump, 0, 1000, "mm",
         "depth: a pixel is at a depth edge when a neighbour's depth differs by more than this");
  v.Real("finger_thickness", p.fingerThickness, 0.1, 10, "cm",
         "depth: thickness of a finger and of a fingertip's pad (circles, ellipses, capsules, "
         "polygons and a hand's fingers, scaled with the hand)");
  v.Real("finger_rise", p.fingerRise, 0, 80, "deg",
         "depth: a fingertip's (circle's) finger rises at this angle from its pad toward the arm "
         "(local -y)");
  v.Real("finger_length", p.fingerLength, 0, 20, "cm",
         "depth: how far a fingertip's finger reaches from the pad's centre, along the table");
  v.Real("palm_thickness", p.palmThickness, 0.1, 10, "cm",
         "depth: thickness of a hand's palm at scale 1");
  v.Real("arm_rise", p.armRise, 0, 80, "deg",
         "depth: a hand's forearm rises at this angle from the wrist (local -y)");
}

void Describe(SensingParams& p, ParamVisitor& v) {
  v.Text("calibration", p.calibration,
         {"calibration YAML written by `proxygrasp calibrate` or `proxygrasp tune` (\"\" maps the "
          "image linearly); its tuned [sensing] values replace the level's, and --set wins",
          Apply::kRestart});
  v.Integer("background_frames", p.backgroundFrames, 0, 600, "frames",
            {"clear-table frames averaged into the background at start (0 = estimate it from the "
             "first frame); unused when the calibration file holds a background",
             Apply::kRestart});
  v.Real("background_warmup", p.backgroundWarmup, 0, 60, "s",
         "how long a background estimated from the first frame (at the scale of a hand, without "
         "fingertips and hands) takes in the frames' per-pixel low, so that what is static from "
         "the start (an illuminator's hot spot) is background and what moved away is not (a "
         "captured or calibrated background needs none); 0 = no warm-up");
  v.Real("background_settle", p.backgroundSettle, 0, 600, "s",
         "for this long after the warm-up, an estimated background comes down fast where the "
         "frame is darker by more than 3 noise deviations (a hand that lay there at the start "
         "has moved), never below the first frame's spatial estimate; 0 = not at all");
  v.Real("background_still", p.backgroundStill, 0, 60, "s",
         "within background_settle: a bright region the warm-up took in comes out of the "
         "background, the whole of it, once part of it shows the table (a hand that lay still "
         "has started to move), and a hand-sized piece of it that ends in 3 fingertips at once; "
         "what is held out goes back in once its region has not moved for this long and no "
         "contact joins it to clear table (a bright mark the hand lay on; a hand that never "
         "moves); 0 = not at all");
  v.Boolean("stills", p.stills,
            "each frame on its own (a folder of unrelated images, a photo): the background is "
            "the frame's spatial estimate alone, nothing is learned between frames, and the "
            "level is set from the frame's own noise and brightest fingertip");
  v.Real("background_learning", p.backgroundLearning, 0, 3600, "s",
         "time constant with which the background follows the frames where nothing touches "
         "and the frame is not brighter than it by 3 noise deviations (slow light changes, "
         "things left on the table; a hovering hand's glow is learned at touch_learning); 0 "
         "keeps it fixed");
  v.Real("touch_learning", p.touchLearning, 0, 36000, "s",
         "time constant with which the background follows the frames under contacts and "
         "where the frame is brighter than it by 3 noise deviations (a hand's glow), so that a "
         "contact that never changes (a light left on, something bright left on the table) "
         "fades; a finger held this long loses 63% of its contrast; 0 = never");
  v.Real("smooth", p.smooth, 0, 2, "cm",
         "deviation of the Gaussian blur that removes sensor noise after the background is "
         "subtracted (0 = none)");
  v.Real("highpass_width", p.highpassWidth, 0, 50, "cm",
         "width of the box blur subtracted from the image (high-pass): glows wider than this "
         "(palms and arms above the surface, uneven lighting) fade, fingertips stay (0 = none)");
  v.Real("highpass_cap", p.highpassCap, 0, 255, "grey",
         "most brightness the high-pass subtracts: a flat hand pressed on the surface, brighter "
         "than a glow, keeps its inside");
  v.Real("gain", p.gain, 0.1, 32, "1",
         "amplification of the high-passed image before the "
         "threshold");
  VisitEnum(v, "threshold_mode", p.thresholdMode, kThresholdModeNames,
            "fixed threshold; automatic (Otsu); or adaptive: contrast_fraction of the brightest "
            "touch of the last contrast_memory seconds, at least noise_factor camera noise "
            "deviations, at most threshold");
  v.Real("threshold", p.threshold, 1, 254, "grey",
         "fixed threshold on the filtered (gained) image; in adaptive mode the highest level");
  v.Real("auto_floor", p.autoFloor, 1, 254, "grey",
         "lowest threshold the automatic (Otsu) mode may pick, so an empty table stays empty");
  v.Real("noise_factor", p.noiseFactor, 1, 50, "1",
         "adaptive mode: the lowest level, in deviations of the camera noise (measured on the "
         "frames), so an empty table stays empty");
  v.Real("contrast_fraction", p.contrastFraction, 0.05, 1, "1",
         "adaptive mode: the level as a fraction of the brightest touch seen lately (above the "
         "level), so a dim table's touches are found and a bright table's glows are not");
  v.Real("contrast_memory", p.contrastMemory, 0.1, 3600, "s",
         "adaptive mode: time constant with which the brightest touch is forgotten");
  v.Integer("morphology", p.morphology, 0, 8, "px",
            "radius of the opening that removes specks and one-pixel bridges (0 = none)");
  v.Real("min_area", p.minArea, 0, 1000, "cm^2", "smallest contact kept");
  v.Real("spacing", p.spacing, 0.05, 5, "cm", "arc-length spacing of resampled contours");
  v.Boolean(
      "subpixel", p.subpixel,
      "move contour points onto the half-contrast edge (sub-pixel) before mapping to the table");
  v.Real("table_cm_per_pixel", p.tableCmPerPixel, 0.02, 2, "cm",
         "pixel size of the table-aligned contact image (instant mode, drawing)");
}

}  // namespace pg
