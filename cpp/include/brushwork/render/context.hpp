// The offscreen OpenGL context through EGL (seed "System prototype"), one per thread.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace brushwork {

// Which EGL path the context took, and what the driver says about itself.
struct RenderInfo {
  std::string backend;   // "egl-device" (a GPU through EGL device enumeration),
                         // "mesa-surfaceless" (software) or "default-display"
  int device_index = -1; // index among the enumerated EGL devices, -1 when none was used
  int device_count = 0;  // EGL devices enumerated
  std::string vendor, renderer, version;  // glGetString
  int max_texture_size = 0;               // px, GL_MAX_TEXTURE_SIZE
};

// One OpenGL 3.3 core context per thread, shared by every Paper and BrushView that thread makes
// (an EGL context is current on one thread at a time: each renders on the thread that made it,
// and make_current elsewhere throws saying so).  Selection
// (Open3D's and MuJoCo's order): BRUSHWORK_RENDER = auto (default) | gpu | software | disable;
// BRUSHWORK_EGL_DEVICE = index of the EGL device to use (range-checked).  auto tries the EGL
// devices (taking the first that initialises), then Mesa's surfaceless platform, then the
// default display.  Failures throw std::runtime_error naming what is missing and what to
// install; a bad variable throws std::invalid_argument.
class RenderContext {
 public:
  static std::shared_ptr<RenderContext> acquire();
  ~RenderContext();
  RenderContext(const RenderContext&) = delete;
  RenderContext& operator=(const RenderContext&) = delete;

  const RenderInfo& info() const { return info_; }
  // a GLSL program built from `vertex` + `fragment` with "#define" lines for `defines`, compiled
  // once per context and shared (a Paper per glyph in a batch must not recompile its shaders);
  // owned by the context: callers must not delete it
  unsigned program(const char* vertex, const char* fragment, const std::vector<std::string>& defines);
  void make_current() const;  // throws if closed
  bool closed() const { return display_ == nullptr; }
  void close();               // idempotent

 private:
  RenderContext() = default;
  void open();
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::thread::id owner_;  // the thread it was made on, the one it is current on
  RenderInfo info_;
  std::map<std::string, unsigned> programs_;
};

}  // namespace brushwork
