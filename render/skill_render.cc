#include "render/skill_render.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <vector>

#include "core/check.h"
#include "core/paths.h"
#include "render/image.h"
#include "render/offscreen_renderer.h"
#include "robot/observation.h"
#include "sim/env.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

enum class OutputKind { kGif, kMp4, kPng };

constexpr int kMaxFps = 50;  // one frame per control step
constexpr int kMaxSeconds = 3600;
constexpr int kSheetColumns = 4;
constexpr int kSheetGap = 4;     // pixels between tiles
constexpr int kFellBorder = 6;   // pixels of red around the tile of a skill that fell
constexpr Rgb kSheetBackground{20, 20, 20};
constexpr Rgb kFellRed{220, 30, 30};
constexpr Rgb kLabelText{255, 255, 255};
constexpr Rgb kLabelBox{30, 30, 30};

OutputKind OutputKindOf(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".gif") return OutputKind::kGif;
  if (extension == ".mp4") return OutputKind::kMp4;
  if (extension == ".png") return OutputKind::kPng;
  throw InputError("render: cannot write '" + path + "': the output must end in .gif, .mp4 or .png");
}

void CheckOptions(const RenderOptions& options, OutputKind kind) {
  if (options.contact_sheet && kind != OutputKind::kPng) {
    throw InputError("render: a contact sheet is a .png, not '" + options.output + "'");
  }
  if (options.fps < 1 || options.fps > kMaxFps) {
    throw InputError("render: fps must be 1 to " + std::to_string(kMaxFps) + " (the control rate), not " +
                     std::to_string(options.fps));
  }
  if (!(options.seconds > 0.0 && options.seconds <= kMaxSeconds)) {
    std::ostringstream message;
    message << "render: seconds must be above 0 and at most " << kMaxSeconds << ", not " << options.seconds;
    throw InputError(message.str());
  }
}

void CheckSkill(const SkillLibrary& library, int skill) {
  if (skill < 0 || skill >= library.num_skills()) {
    throw InputError("render: skill " + std::to_string(skill) + " is not in 0 to " +
                     std::to_string(library.num_skills() - 1) + " (" + library.path() + " has " +
                     std::to_string(library.num_skills()) + " skills)");
  }
}

int ControlSteps(double seconds) { return std::max(1, static_cast<int>(std::lround(seconds / a1::kControlDt))); }

// Control steps between frames: the frame rate is 50 Hz divided by a whole number.
int FrameInterval(int fps) { return std::max(1, static_cast<int>(std::lround(1.0 / (fps * a1::kControlDt)))); }

// One skill on the nominal robot, stepped as skilld steps it.
class SkillRollout {
 public:
  SkillRollout(const SkillLibrary& library, const mjModel& model, int skill, int steps, uint64_t seed)
      : skill_(skill), env_(model, NominalConfig(steps, library), seed), policy_(library) {
    env_.Reset();
  }

  Termination Step() {
    BuildMotionObservation(env_.state(), motion_.data());
    policy_.Act(motion_.data(), previous_.data(), skill_, action_.data());
    previous_ = action_;
    ++steps_done_;
    return env_.Step(action_.data());
  }

  const mjData& data() const { return env_.data(); }
  double seconds() const { return steps_done_ * a1::kControlDt; }

 private:
  // No randomisation, no time-out before `steps`, and the library's target filter.
  static EnvConfig NominalConfig(int steps, const SkillLibrary& library) {
    EnvConfig config;
    config.randomization.DisableAll();
    config.episode_steps = steps + 1;
    config.action_filter_hz = library.action_filter_hz();
    config.action_filter_order = library.action_filter_order();
    return config;
  }

  int skill_;
  Env env_;
  PolicyRunner policy_;
  std::vector<float> motion_ = std::vector<float>(kMotionObsSize);
  std::vector<float> action_ = std::vector<float>(kActionSize, 0.0f);
  std::vector<float> previous_ = std::vector<float>(kActionSize, 0.0f);
  int steps_done_ = 0;
};

void WarnFall(int skill, const SkillRollout& rollout, Termination ending) {
  spdlog::warn("render: skill {} fell after {:.2f} s ({}); filmed up to the fall", skill, rollout.seconds(),
               ToString(ending));
}

std::unique_ptr<VideoWriter> OpenVideo(const RenderOptions& options, OutputKind kind, int frame_interval) {
  const double frame_seconds = frame_interval * a1::kControlDt;
  if (kind == OutputKind::kGif) {
    return std::make_unique<GifWriter>(options.output, options.width, options.height,
                                       static_cast<int>(std::lround(frame_seconds * 100.0)));
  }
  return std::make_unique<Mp4Writer>(options.output, options.width, options.height, 1.0 / frame_seconds);
}

void RenderVideo(const SkillLibrary& library, const mjModel& model, const RenderOptions& options, OutputKind kind) {
  OffscreenRenderer renderer(model, options.width, options.height);
  const int interval = FrameInterval(options.fps);
  const int steps = ControlSteps(options.seconds);
  const std::unique_ptr<VideoWriter> video = OpenVideo(options, kind, interval);
  SkillRollout rollout(library, model, options.skill, steps, options.seed);
  int frames = 0;
  for (int step = 0; step < steps; ++step) {
    if (step % interval == 0) {
      video->AddFrame(renderer.Render(rollout.data()));
      ++frames;
    }
    const Termination ending = rollout.Step();
    if (IsFailure(ending)) {
      video->AddFrame(renderer.Render(rollout.data()));  // the fall itself ends the video
      ++frames;
      WarnFall(options.skill, rollout, ending);
      break;
    }
  }
  video->Close();
  spdlog::info("render: wrote {}: skill {}, {} frames at {:.3g} fps", options.output, options.skill, frames,
               1.0 / (interval * a1::kControlDt));
}

// The robot after `steps` control steps of `skill`, or at its fall.
struct Still {
  Image image;
  bool fell = false;
};

Still FilmStill(const SkillLibrary& library, const mjModel& model, OffscreenRenderer& renderer, int skill,
                const RenderOptions& options) {
  const int steps = ControlSteps(options.seconds);
  SkillRollout rollout(library, model, skill, steps, options.seed);
  Still still;
  for (int step = 0; step < steps && !still.fell; ++step) {
    const Termination ending = rollout.Step();
    if (IsFailure(ending)) {
      still.fell = true;
      WarnFall(skill, rollout, ending);
    }
  }
  still.image = renderer.Render(rollout.data());
  return still;
}

void RenderStill(const SkillLibrary& library, const mjModel& model, const RenderOptions& options) {
  OffscreenRenderer renderer(model, options.width, options.height);
  WritePng(FilmStill(library, model, renderer, options.skill, options).image, options.output);
  spdlog::info("render: wrote {}: skill {} after {:.2f} s", options.output, options.skill, options.seconds);
}

void DrawBorder(Image& image, int thickness, Rgb color) {
  FillRect(image, 0, 0, image.width, thickness, color);
  FillRect(image, 0, image.height - thickness, image.width, thickness, color);
  FillRect(image, 0, 0, thickness, image.height, color);
  FillRect(image, image.width - thickness, 0, thickness, image.height, color);
}

void RenderContactSheet(const SkillLibrary& library, const mjModel& model, const RenderOptions& options) {
  OffscreenRenderer renderer(model, options.width, options.height);
  const int skills = library.num_skills();
  const int columns = std::min(skills, kSheetColumns);
  const int rows = (skills + kSheetColumns - 1) / kSheetColumns;
  Image sheet(columns * (options.width + kSheetGap) + kSheetGap, rows * (options.height + kSheetGap) + kSheetGap,
              kSheetBackground);
  const int label_scale = std::max(1, options.height / 120);  // 3 at 360 px: digits 21 px tall
  int fell = 0;
  for (int skill = 0; skill < skills; ++skill) {
    Still still = FilmStill(library, model, renderer, skill, options);
    if (still.fell) {
      DrawBorder(still.image, kFellBorder, kFellRed);
      ++fell;
    }
    DrawNumber(still.image, kFellBorder + 2, kFellBorder + 2, skill, label_scale, kLabelText, kLabelBox);
    Blit(still.image, kSheetGap + (skill % kSheetColumns) * (options.width + kSheetGap),
         kSheetGap + (skill / kSheetColumns) * (options.height + kSheetGap), sheet);
  }
  WritePng(sheet, options.output);
  spdlog::info("render: wrote {}: {} skills after {:.2f} s, {} fell (red border)", options.output, skills,
               options.seconds, fell);
}

}  // namespace

int RunRender(const RenderOptions& options) {
  const OutputKind kind = OutputKindOf(options.output);
  CheckOptions(options, kind);
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(options.library));
  if (!options.contact_sheet) CheckSkill(library, options.skill);
  const MjModelPtr model = LoadMjModel(EnvConfig().model);
  if (options.contact_sheet) {
    RenderContactSheet(library, *model, options);
  } else if (kind == OutputKind::kPng) {
    RenderStill(library, *model, options);
  } else {
    RenderVideo(library, *model, options, kind);
  }
  return 0;
}

}  // namespace flsd
