// EGL context: a GPU through EGL device enumeration, else Mesa's surfaceless software renderer,
// else the default display (the order of Open3D's EGLOffscreenContext).  libEGL is opened with
// dlopen so that a machine without it can still import brushwork and use the brush.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdint>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "brushwork/render.hpp"
#include "gl_api.hpp"
#include "gl_util.hpp"

namespace brushwork {
namespace gl {
#define BRUSHWORK_GL_DEFINE(ret, name, args) ret(*name) args = nullptr;
BRUSHWORK_GL_FUNCTIONS(BRUSHWORK_GL_DEFINE)
#undef BRUSHWORK_GL_DEFINE

const char* load(ProcGetter get) {
#define BRUSHWORK_GL_LOAD(ret, name, args)                                        \
  name = reinterpret_cast<ret(*) args>(get("gl" #name));                          \
  if (name == nullptr) return "gl" #name;
  BRUSHWORK_GL_FUNCTIONS(BRUSHWORK_GL_LOAD)
#undef BRUSHWORK_GL_LOAD
  return nullptr;
}
}  // namespace gl

namespace {

constexpr const char* kInstallHint =
    "install EGL and Mesa's software OpenGL (Debian/Ubuntu: sudo apt install libegl1 "
    "libegl-mesa0 libgl1-mesa-dri; with an NVIDIA GPU the driver's libEGL_nvidia is used)";

// the EGL entry points, resolved from the dlopen'ed library
struct Egl {
  void* lib = nullptr;
  PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
  PFNEGLGETDISPLAYPROC GetDisplay = nullptr;
  PFNEGLINITIALIZEPROC Initialize = nullptr;
  PFNEGLTERMINATEPROC Terminate = nullptr;
  PFNEGLBINDAPIPROC BindAPI = nullptr;
  PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
  PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
  PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
  PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
  PFNEGLQUERYSTRINGPROC QueryString = nullptr;
  PFNEGLGETERRORPROC GetError = nullptr;
  PFNEGLQUERYDEVICESEXTPROC QueryDevices = nullptr;          // EGL_EXT_device_enumeration
  PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplay = nullptr;  // EGL_EXT_platform_base
};

Egl& egl() {
  static Egl e;
  static std::once_flag once;
  std::call_once(once, [] {
    e.lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
    if (e.lib == nullptr) e.lib = dlopen("libEGL.so", RTLD_NOW | RTLD_LOCAL);
    if (e.lib == nullptr) return;
    auto sym = [](const char* name) { return dlsym(e.lib, name); };
    e.GetProcAddress = reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(sym("eglGetProcAddress"));
    e.GetDisplay = reinterpret_cast<PFNEGLGETDISPLAYPROC>(sym("eglGetDisplay"));
    e.Initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(sym("eglInitialize"));
    e.Terminate = reinterpret_cast<PFNEGLTERMINATEPROC>(sym("eglTerminate"));
    e.BindAPI = reinterpret_cast<PFNEGLBINDAPIPROC>(sym("eglBindAPI"));
    e.ChooseConfig = reinterpret_cast<PFNEGLCHOOSECONFIGPROC>(sym("eglChooseConfig"));
    e.CreateContext = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(sym("eglCreateContext"));
    e.DestroyContext = reinterpret_cast<PFNEGLDESTROYCONTEXTPROC>(sym("eglDestroyContext"));
    e.MakeCurrent = reinterpret_cast<PFNEGLMAKECURRENTPROC>(sym("eglMakeCurrent"));
    e.QueryString = reinterpret_cast<PFNEGLQUERYSTRINGPROC>(sym("eglQueryString"));
    e.GetError = reinterpret_cast<PFNEGLGETERRORPROC>(sym("eglGetError"));
    if (e.GetProcAddress != nullptr) {
      e.QueryDevices =
          reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(e.GetProcAddress("eglQueryDevicesEXT"));
      e.GetPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
          e.GetProcAddress("eglGetPlatformDisplayEXT"));
    }
  });
  return e;
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v == nullptr ? std::string() : std::string(v);
}

// opening and closing contexts, from any thread (recursive: a failed open closes)
std::recursive_mutex& context_mutex() {
  static std::recursive_mutex mu;
  return mu;
}

// open contexts per EGL display: a display is initialised once for every thread's context of a
// process, so it is terminated only when its last context closes
std::map<EGLDisplay, int>& display_users() {
  static std::map<EGLDisplay, int> users;
  return users;
}

// eglTerminate `dpy` unless another context still lives on it
void release_display(Egl& e, EGLDisplay dpy) {
  if (display_users()[dpy] == 0) e.Terminate(dpy);
}

// an OpenGL 3.3 core context on `dpy`, or null (the display is terminated on failure)
EGLContext try_context(Egl& e, EGLDisplay dpy, std::string& why) {
  EGLint major = 0, minor = 0;
  if (dpy == EGL_NO_DISPLAY || e.Initialize(dpy, &major, &minor) != EGL_TRUE) {
    why = "eglInitialize failed";
    return EGL_NO_CONTEXT;
  }
  if (e.BindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    why = "no desktop OpenGL API on this display";
    release_display(e, dpy);
    return EGL_NO_CONTEXT;
  }
  // no surface at all: we render into framebuffer objects (EGL_KHR_surfaceless_context)
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint n = 0;
  if (e.ChooseConfig(dpy, config_attribs, &config, 1, &n) != EGL_TRUE || n < 1) config = nullptr;
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = e.CreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT) {
    why = "no OpenGL 3.3 core context";
    release_display(e, dpy);
    return EGL_NO_CONTEXT;
  }
  if (e.MakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx) != EGL_TRUE) {
    why = "surfaceless eglMakeCurrent failed";
    e.DestroyContext(dpy, ctx);
    release_display(e, dpy);
    return EGL_NO_CONTEXT;
  }
  return ctx;
}

// this thread's context: an EGL context is current on one thread at a time, so each thread that
// renders gets its own (shaders compiled once per thread)
std::weak_ptr<RenderContext>& thread_slot() {
  thread_local std::weak_ptr<RenderContext> slot;
  return slot;
}

}  // namespace

std::shared_ptr<RenderContext> RenderContext::acquire() {
  std::lock_guard<std::recursive_mutex> lock(context_mutex());
  auto ctx = thread_slot().lock();
  if (ctx && !ctx->closed()) return ctx;
  ctx = std::shared_ptr<RenderContext>(new RenderContext());
  ctx->open();
  thread_slot() = ctx;
  return ctx;
}

namespace {

constexpr int kMaxEglDevices = 16;  // EGL devices enumerated at most

// BRUSHWORK_RENDER checked: auto (unset), gpu or software; disable throws
std::string render_mode() {
  const std::string mode = env("BRUSHWORK_RENDER").empty() ? "auto" : env("BRUSHWORK_RENDER");
  if (mode != "auto" && mode != "gpu" && mode != "software" && mode != "disable")
    throw std::invalid_argument("BRUSHWORK_RENDER = '" + mode +
                                "': expected auto, gpu, software or disable");
  if (mode == "disable")
    throw std::runtime_error("rendering is disabled (BRUSHWORK_RENDER=disable); unset it to render");
  return mode;
}

// the EGL library with its core entry points, or a runtime_error saying what to install
Egl& loaded_egl() {
  Egl& e = egl();
  if (e.lib == nullptr)
    throw std::runtime_error(std::string("no EGL library (libEGL.so.1 not found): ") + kInstallHint);
  if (e.GetProcAddress == nullptr || e.Initialize == nullptr || e.CreateContext == nullptr)
    throw std::runtime_error(std::string("libEGL.so.1 lacks core EGL 1.4 entry points: ") +
                             kInstallHint);
  return e;
}

// the device the user asked for (BRUSHWORK_EGL_DEVICE), -1 for none; range-checked once the
// devices are known
int wanted_device() {
  const std::string dev_env = env("BRUSHWORK_EGL_DEVICE");
  if (dev_env.empty()) return -1;
  char* end = nullptr;
  const long v = std::strtol(dev_env.c_str(), &end, 10);
  if (end == dev_env.c_str() || *end != '\0' || v < 0)
    throw std::invalid_argument("BRUSHWORK_EGL_DEVICE = '" + dev_env + "': expected a device index 0, 1, ...");
  return static_cast<int>(v);
}

// Mesa lists its software device too: in auto mode it is left to the surfaceless path
bool software_device(Egl& e, EGLDeviceEXT device) {
  auto* query_device_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(e.GetProcAddress("eglQueryDeviceStringEXT"));
  if (query_device_string == nullptr) return false;
  const char* ext = query_device_string(device, EGL_EXTENSIONS);
  return ext != nullptr && std::string(ext).find("EGL_MESA_device_software") != std::string::npos;
}

// where a context was made: its display and context (EGL_NO_CONTEXT while none), and what
// each path tried said
struct Opened {
  EGLDisplay dpy = EGL_NO_DISPLAY;
  EGLContext ctx = EGL_NO_CONTEXT;
  std::string tried;
};

// 1. a GPU through EGL device enumeration: the wanted device, or the first that initialises
void try_devices(Egl& e, int wanted, RenderInfo& info, Opened& o) {
  EGLDeviceEXT devices[kMaxEglDevices];
  EGLint count = 0;
  if (e.QueryDevices(kMaxEglDevices, devices, &count) != EGL_TRUE) count = 0;
  info.device_count = count;
  if (wanted >= count)
    throw std::invalid_argument("BRUSHWORK_EGL_DEVICE = " + std::to_string(wanted) +
                                " is out of range: " + std::to_string(count) +
                                " EGL device(s), indices 0.." + std::to_string(count - 1));
  for (int i = 0; i < count && o.ctx == EGL_NO_CONTEXT; ++i) {
    if (wanted >= 0 && i != wanted) continue;
    if (wanted < 0 && software_device(e, devices[i])) continue;
    o.dpy = e.GetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    std::string why;
    o.ctx = try_context(e, o.dpy, why);
    if (o.ctx != EGL_NO_CONTEXT) {
      info.backend = "egl-device";
      info.device_index = i;
    } else {
      o.tried += "device " + std::to_string(i) + ": " + why + "; ";
    }
  }
}

// a context on `dpy`, the path named `backend` (and `label` in the list of what was tried)
void try_display(Egl& e, EGLDisplay dpy, const char* backend, const char* label, RenderInfo& info, Opened& o) {
  o.dpy = dpy;
  std::string why;
  o.ctx = try_context(e, dpy, why);
  if (o.ctx != EGL_NO_CONTEXT) info.backend = backend;
  else o.tried += std::string(label) + ": " + why + "; ";
}

// the driver's name and limits
void read_gl_info(RenderInfo& info) {
  auto str = [](GLenum name) {
    const GLubyte* s = gl::GetString(name);
    return s == nullptr ? std::string("?") : std::string(reinterpret_cast<const char*>(s));
  };
  info.vendor = str(GL_VENDOR);
  info.renderer = str(GL_RENDERER);
  info.version = str(GL_VERSION);
  GLint max_tex = 0;
  gl::GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
  info.max_texture_size = max_tex;
}

}  // namespace

void RenderContext::open() {
  const std::string mode = render_mode();
  Egl& e = loaded_egl();
  const int wanted = wanted_device();
  Opened o;
  // 1. a GPU through EGL device enumeration (skipped for software)
  if (mode != "software" && e.QueryDevices != nullptr && e.GetPlatformDisplay != nullptr) {
    try_devices(e, wanted, info_, o);
  } else if (wanted >= 0 && mode != "software") {
    throw std::invalid_argument("BRUSHWORK_EGL_DEVICE is set but this EGL has no device "
                                "enumeration (EGL_EXT_device_enumeration)");
  }
  if (o.ctx == EGL_NO_CONTEXT && mode == "gpu")
    throw std::runtime_error("BRUSHWORK_RENDER=gpu but no EGL GPU device initialised (" + o.tried +
                             "); install the NVIDIA driver's EGL (libnvidia-egl / libEGL_nvidia) "
                             "or use BRUSHWORK_RENDER=auto");
  // 2. Mesa's surfaceless platform (llvmpipe when there is no GPU)
  if (o.ctx == EGL_NO_CONTEXT && e.GetPlatformDisplay != nullptr)
    try_display(e, e.GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                "mesa-surfaceless", "mesa surfaceless", info_, o);
  // 3. the default display
  if (o.ctx == EGL_NO_CONTEXT)
    try_display(e, e.GetDisplay(EGL_DEFAULT_DISPLAY), "default-display", "default display", info_, o);
  if (o.ctx == EGL_NO_CONTEXT)
    throw std::runtime_error("no usable EGL display with OpenGL 3.3 core (" + o.tried + "): " + kInstallHint);

  display_ = o.dpy;
  context_ = o.ctx;
  owner_ = std::this_thread::get_id();
  display_users()[display_] += 1;
  if (const char* missing = gl::load(reinterpret_cast<gl::ProcGetter>(e.GetProcAddress))) {
    close();
    throw std::runtime_error(std::string("OpenGL entry point ") + missing + " is missing: " + kInstallHint);
  }
  read_gl_info(info_);
}

unsigned RenderContext::program(const char* vertex, const char* fragment,
                                const std::vector<std::string>& defines) {
  // key: the two sources (their addresses: they are string constants) and the switches
  std::string key = std::to_string(reinterpret_cast<std::uintptr_t>(vertex)) + "/" +
                    std::to_string(reinterpret_cast<std::uintptr_t>(fragment));
  for (const auto& d : defines) key += "/" + d;
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;
  make_current();
  const unsigned prog = glu::program(vertex, fragment, defines);
  programs_.emplace(key, prog);
  return prog;
}

void RenderContext::make_current() const {
  if (closed()) throw std::runtime_error("the render context is closed");
  if (std::this_thread::get_id() != owner_)
    throw std::runtime_error("a Paper or BrushView renders on the thread that made it (each thread "
                             "has its own GL context): make one on this thread");
  Egl& e = egl();
  if (e.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE)
    throw std::runtime_error("eglMakeCurrent failed");
}

void RenderContext::close() {
  std::lock_guard<std::recursive_mutex> lock(context_mutex());
  if (display_ == nullptr) return;
  Egl& e = egl();
  // (released only on its own thread: elsewhere it is not current, and the call would fail)
  if (std::this_thread::get_id() == owner_) e.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != nullptr) e.DestroyContext(display_, context_);
  display_users()[display_] -= 1;
  release_display(e, display_);
  programs_.clear();  // they died with the context
  display_ = nullptr;
  context_ = nullptr;
}

RenderContext::~RenderContext() { close(); }

}  // namespace brushwork
