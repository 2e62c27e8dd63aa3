#pragma once
// `flsd render`: a skill of a library rolled out on the nominal simulated A1 (as
// tests/skills/runtime/shipped_library_test.cc and skilld run skills: Eigen inference at 50 Hz,
// no randomisation), filmed by a camera that follows the robot. A video, a still, or one still
// per skill tiled into a contact sheet.

#include <cstdint>
#include <string>

namespace flsd {

struct RenderOptions {
  std::string library;         // skill library (.safetensors), resolved with ResolveDataPath
  int skill = 0;               // which skill to film, 0 to num_skills - 1; a sheet has them all
  bool contact_sheet = false;  // every skill, one still each, tiled 4 across into one PNG
  double seconds = 4.0;        // of rollout: the video's length, or when the stills are taken
  int fps = 25;                // 1 to 50; frames are taken every round(50 / fps) control steps
  int width = 480;             // pixels of a frame (a tile of the contact sheet)
  int height = 360;
  uint64_t seed = 1;           // of the initial state (the joint pose is drawn at reset)
  std::string output;          // .gif, .mp4 (needs ffmpeg) or .png (the last frame); .png for a sheet
};

// Rolls out and writes `options.output`. A skill that falls is filmed up to its fall (a warning
// says so) and the file is still written; on a contact sheet its tile has a red border. Returns
// 0. Throws InputError, before any rollout, for a skill out of range, an unsupported extension
// or other bad options, and naming the path if the output cannot be written.
int RunRender(const RenderOptions& options);

}  // namespace flsd
