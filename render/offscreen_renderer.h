#pragma once
// Pictures of the simulated A1 without a display: MuJoCo's renderer drawing into an OSMesa
// (software OpenGL) context, seen by a camera that follows the robot.

#include <mujoco/mujoco.h>

#include <memory>
#include <vector>

#include "render/image.h"
#include "sim/mujoco_model.h"

struct osmesa_context;  // GL/osmesa.h's OSMesaContext points to one

namespace flsd {

struct OsMesaContextDeleter {
  void operator()(osmesa_context* context) const;
};

// Where the camera sits relative to the robot's trunk. MuJoCo's convention: azimuth in degrees
// about the world z axis (0 looks along +x), elevation in degrees (negative looks down).
struct TrackingView {
  double distance = 1.5;     // m from the trunk
  double azimuth = -135.0;   // from the robot's front left, a 3/4 view of its front and side
  double elevation = -20.0;
};

// Renders on the calling thread, which must be the thread that made the renderer. Each renderer
// owns its GL context and makes it current to render, so several may exist in one thread, but
// one per process is the intended use. Rendering is in software (Mesa's llvmpipe): about 0.1 s
// per 480x360 frame, most of it the model's 4x multisampling.
// Not copyable or movable: MuJoCo's scene and context hold GL objects of this context.
class OffscreenRenderer {
 public:
  // Renders states of `model` (copied) in width x height images. Throws InputError if the size
  // exceeds the model's offscreen buffer (<visual><global offwidth offheight>) or OSMesa cannot
  // make a context.
  OffscreenRenderer(const mjModel& model, int width, int height, TrackingView view = {});
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // A picture of `data` (of the model given at construction, or of a copy of it) as mj_forward
  // or mj_step left it (body and geom poses), with the camera looking at the trunk.
  Image Render(const mjData& data);

 private:
  // Makes the context current on this thread: Bind() says whether OSMesa did, MakeCurrent()
  // throws InputError if it did not.
  bool Bind();
  void MakeCurrent();

  MjModelPtr model_;
  int width_, height_;
  int trunk_body_;
  std::unique_ptr<osmesa_context, OsMesaContextDeleter> gl_;
  std::vector<unsigned char> framebuffer_;  // OSMesa's window buffer, RGBA; MuJoCo draws to its own FBO
  std::vector<unsigned char> pixels_;       // mjr_readPixels' RGB rows, bottom first
  mjvScene scene_;
  mjrContext context_;
  mjvOption option_;
  mjvPerturb perturb_;
  mjvCamera camera_;
};

}  // namespace flsd
