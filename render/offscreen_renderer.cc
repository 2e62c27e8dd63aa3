#include "render/offscreen_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <string>

#include "core/check.h"
#include "sim/mujoco_model.h"

namespace flsd {
namespace {

constexpr int kMaxGeoms = 2000;  // the A1 and its floor have about 40
// MuJoCo's default shadow map is 4096 pixels square; drawing it in software costs a fifth of a
// 480x360 frame, and 1024 looks the same at such sizes.
constexpr int kMaxShadowMapSize = 1024;

}  // namespace

void OsMesaContextDeleter::operator()(osmesa_context* context) const { OSMesaDestroyContext(context); }

OffscreenRenderer::OffscreenRenderer(const mjModel& model, int width, int height, TrackingView view)
    : model_(CopyMjModel(model)),
      width_(width),
      height_(height),
      trunk_body_(A1ModelIndex::Find(model).trunk_body) {
  const int max_width = model.vis.global.offwidth, max_height = model.vis.global.offheight;
  if (width < 1 || height < 1 || width > max_width || height > max_height) {
    throw InputError("render: a " + std::to_string(width) + "x" + std::to_string(height) +
                     " picture does not fit the model's offscreen buffer of " + std::to_string(max_width) + "x" +
                     std::to_string(max_height) + " (<visual><global offwidth offheight>)");
  }
  // RGBA with 24 depth and 8 stencil bits, what MuJoCo's renderer asks of a window
  gl_.reset(OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr));
  if (!gl_) throw InputError("render: OSMesa cannot create an OpenGL context");
  framebuffer_.resize(4 * static_cast<size_t>(max_width) * max_height);
  MakeCurrent();

  mjv_defaultScene(&scene_);
  mjr_defaultContext(&context_);
  mjv_defaultOption(&option_);
  mjv_defaultPerturb(&perturb_);
  mjv_defaultCamera(&camera_);
  model_->vis.quality.shadowsize = std::min(model_->vis.quality.shadowsize, kMaxShadowMapSize);
  mjv_makeScene(model_.get(), &scene_, kMaxGeoms);
  mjr_makeContext(model_.get(), &context_, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &context_);
  camera_.type = mjCAMERA_FREE;
  camera_.distance = view.distance;
  camera_.azimuth = view.azimuth;
  camera_.elevation = view.elevation;
  pixels_.resize(3 * static_cast<size_t>(width_) * height_);
}

OffscreenRenderer::~OffscreenRenderer() {
  // MuJoCo frees its GL objects in the current context: make it ours (a destructor cannot
  // report a failure; the context is destroyed right after anyway).
  Bind();
  mjr_freeContext(&context_);
  mjv_freeScene(&scene_);
}

bool OffscreenRenderer::Bind() {
  return OSMesaMakeCurrent(gl_.get(), framebuffer_.data(), GL_UNSIGNED_BYTE, model_->vis.global.offwidth,
                           model_->vis.global.offheight);
}

void OffscreenRenderer::MakeCurrent() {
  if (!Bind()) throw InputError("render: OSMesa cannot make its OpenGL context current");
}

Image OffscreenRenderer::Render(const mjData& data) {
  MakeCurrent();
  std::copy_n(data.xpos + 3 * trunk_body_, 3, camera_.lookat);
  // MuJoCo 2.2 takes mjData* here for its scratch stack; the simulation state is only read.
  mjv_updateScene(model_.get(), const_cast<mjData*>(&data), &option_, &perturb_, &camera_, mjCAT_ALL, &scene_);
  const mjrRect viewport = {0, 0, width_, height_};
  mjr_render(viewport, &scene_, &context_);
  mjr_readPixels(pixels_.data(), nullptr, viewport, &context_);
  // OpenGL's rows run bottom up, an image's top down
  Image image(width_, height_);
  const size_t row_bytes = 3 * static_cast<size_t>(width_);
  for (int y = 0; y < height_; ++y) {
    std::copy_n(&pixels_[(height_ - 1 - y) * row_bytes], row_bytes, &image.rgb[y * row_bytes]);
  }
  return image;
}

}  // namespace flsd
