#include "render/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <dlfcn.h>

#include <array>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "core/errors.h"

namespace hribench::render {

std::string_view to_string(Backend backend) {
  switch (backend) {
    case Backend::kOsmesa:
      return "osmesa";
    case Backend::kEgl:
      return "egl";
    case Backend::kNone:
      return "none";
  }
  return "unknown";
}

Backend parse_backend(std::string_view text, std::string_view where) {
  if (text == "osmesa") return Backend::kOsmesa;
  if (text == "egl") return Backend::kEgl;
  if (text == "none") return Backend::kNone;
  throw core::InputError(std::string(where), "one of osmesa, egl, none",
                         "'" + std::string(text) + "'");
}

namespace {

using GlGetStringFn = const unsigned char* (*)(unsigned int);
constexpr unsigned int kGlRenderer = 0x1F01;
constexpr unsigned int kGlVersion = 0x1F02;

// The one GL platform this process uses (MuJoCo's glad binds GL functions once per process).
std::mutex platform_mutex;
Backend platform = Backend::kNone;

[[noreturn]] void fail(Backend backend, const std::string& why) {
  throw core::InputError::Message(std::string(to_string(backend)),
                                  "no usable GL context: " + why);
}

// Fails if this process already loaded the other GL platform; with `claim`, records `backend`.
void check_platform(Backend backend, bool claim) {
  std::lock_guard<std::mutex> lock(platform_mutex);
  if (platform != Backend::kNone && platform != backend) {
    fail(backend, "this process already renders through " + std::string(to_string(platform)) +
                      " (MuJoCo binds GL functions once per process; use one back end)");
  }
  if (claim) platform = backend;
}

// dlopen()s the first library of `names` that loads, RTLD_LOCAL (see gl_context.h).
// The environment variable `override_env`, when set, replaces the list.
void* open_library(Backend backend, const char* override_env,
                   std::vector<std::string> names) {
  if (const char* name = std::getenv(override_env); name != nullptr && *name != '\0') {
    names = {name};
  }
  std::string errors;
  for (const std::string& name : names) {
    if (void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL)) return handle;
    const char* error = dlerror();
    errors += (errors.empty() ? "" : "; ") + std::string(error != nullptr ? error : name);
  }
  fail(backend, "cannot load the platform library (" + errors + ")");
}

template <typename Fn>
Fn symbol(Backend backend, void* library, const char* name) {
  void* address = dlsym(library, name);
  if (address == nullptr) fail(backend, std::string("the platform library lacks ") + name);
  return reinterpret_cast<Fn>(address);
}

std::string gl_string(GlGetStringFn get_string, unsigned int name) {
  const unsigned char* text = get_string != nullptr ? get_string(name) : nullptr;
  return text != nullptr ? std::string(reinterpret_cast<const char*>(text)) : std::string();
}

// ---------------------------------------------------------------------------------------------
// OSMesa: a software context drawing into a small host buffer (MuJoCo renders into its own
// offscreen framebuffer object, so the window buffer is never read).
struct OsmesaApi {
  void* library = nullptr;
  decltype(&OSMesaCreateContextExt) create = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaGetCurrentContext) get_current = nullptr;
  decltype(&OSMesaDestroyContext) destroy = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc = nullptr;
};

const OsmesaApi& osmesa_api() {
  static const OsmesaApi api = [] {
    OsmesaApi a;
    a.library = open_library(Backend::kOsmesa, "HRIBENCH_OSMESA_LIBRARY",
                             {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"});
    a.create = symbol<decltype(a.create)>(Backend::kOsmesa, a.library, "OSMesaCreateContextExt");
    a.make_current = symbol<decltype(a.make_current)>(Backend::kOsmesa, a.library,
                                                      "OSMesaMakeCurrent");
    a.get_current = symbol<decltype(a.get_current)>(Backend::kOsmesa, a.library,
                                                    "OSMesaGetCurrentContext");
    a.destroy = symbol<decltype(a.destroy)>(Backend::kOsmesa, a.library, "OSMesaDestroyContext");
    a.get_proc = symbol<decltype(a.get_proc)>(Backend::kOsmesa, a.library,
                                              "OSMesaGetProcAddress");
    return a;
  }();
  return api;
}

class OsmesaContext final : public GlContext {
 public:
  OsmesaContext() {
    // MuJoCo's glad would take a globally visible eglGetProcAddress over OSMesa's loader.
    if (dlsym(RTLD_DEFAULT, "eglGetProcAddress") != nullptr) {
      fail(Backend::kOsmesa,
           "libEGL is linked into this program, so MuJoCo would load GL functions through EGL; "
           "link without libEGL (the render layer loads it itself) or use --backend egl");
    }
    const OsmesaApi& api = osmesa_api();
    context_ = api.create(OSMESA_RGBA, 24, 8, 0, nullptr);
    if (context_ == nullptr) fail(Backend::kOsmesa, "OSMesaCreateContextExt failed");
    make_current();
    auto get_string = reinterpret_cast<GlGetStringFn>(api.get_proc("glGetString"));
    gl_renderer_ = gl_string(get_string, kGlRenderer);
    gl_version_ = gl_string(get_string, kGlVersion);
    if (gl_version_.empty()) fail(Backend::kOsmesa, "glGetString(GL_VERSION) returned nothing");
  }
  ~OsmesaContext() override {
    const OsmesaApi& api = osmesa_api();
    if (api.get_current() == context_) api.make_current(nullptr, nullptr, 0, 0, 0);
    api.destroy(context_);
  }
  void make_current() override {
    const OsmesaApi& api = osmesa_api();
    if (api.get_current() == context_) return;
    if (!api.make_current(context_, window_.data(), GL_UNSIGNED_BYTE, kWindowSize, kWindowSize)) {
      fail(Backend::kOsmesa, "OSMesaMakeCurrent failed");
    }
  }
  Backend backend() const override { return Backend::kOsmesa; }

 private:
  static constexpr int kWindowSize = 8;
  OSMesaContext context_ = nullptr;
  std::array<unsigned char, 4 * kWindowSize * kWindowSize> window_{};
};

// ---------------------------------------------------------------------------------------------
// EGL: a surfaceless OpenGL (not ES) context on an EGL device (a GPU, or Mesa's software device),
// else on Mesa's surfaceless platform, else on the default display.
struct EglApi {
  void* library = nullptr;
  PFNEGLGETPROCADDRESSPROC get_proc = nullptr;
  PFNEGLGETERRORPROC get_error = nullptr;
  PFNEGLGETDISPLAYPROC get_display = nullptr;
  PFNEGLINITIALIZEPROC initialize = nullptr;
  PFNEGLQUERYSTRINGPROC query_string = nullptr;
  PFNEGLCHOOSECONFIGPROC choose_config = nullptr;
  PFNEGLBINDAPIPROC bind_api = nullptr;
  PFNEGLCREATECONTEXTPROC create_context = nullptr;
  PFNEGLDESTROYCONTEXTPROC destroy_context = nullptr;
  PFNEGLMAKECURRENTPROC make_current = nullptr;
  PFNEGLGETCURRENTCONTEXTPROC get_current = nullptr;
  PFNEGLCREATEPBUFFERSURFACEPROC create_pbuffer = nullptr;
  PFNEGLQUERYDEVICESEXTPROC query_devices = nullptr;             // may be null
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;  // may be null
};

const EglApi& egl_api() {
  static const EglApi api = [] {
    EglApi a;
    const Backend b = Backend::kEgl;
    a.library = open_library(b, "HRIBENCH_EGL_LIBRARY", {"libEGL.so.1", "libEGL.so"});
    a.get_proc = symbol<PFNEGLGETPROCADDRESSPROC>(b, a.library, "eglGetProcAddress");
    a.get_error = symbol<PFNEGLGETERRORPROC>(b, a.library, "eglGetError");
    a.get_display = symbol<PFNEGLGETDISPLAYPROC>(b, a.library, "eglGetDisplay");
    a.initialize = symbol<PFNEGLINITIALIZEPROC>(b, a.library, "eglInitialize");
    a.query_string = symbol<PFNEGLQUERYSTRINGPROC>(b, a.library, "eglQueryString");
    a.choose_config = symbol<PFNEGLCHOOSECONFIGPROC>(b, a.library, "eglChooseConfig");
    a.bind_api = symbol<PFNEGLBINDAPIPROC>(b, a.library, "eglBindAPI");
    a.create_context = symbol<PFNEGLCREATECONTEXTPROC>(b, a.library, "eglCreateContext");
    a.destroy_context = symbol<PFNEGLDESTROYCONTEXTPROC>(b, a.library, "eglDestroyContext");
    a.make_current = symbol<PFNEGLMAKECURRENTPROC>(b, a.library, "eglMakeCurrent");
    a.get_current = symbol<PFNEGLGETCURRENTCONTEXTPROC>(b, a.library, "eglGetCurrentContext");
    a.create_pbuffer =
        symbol<PFNEGLCREATEPBUFFERSURFACEPROC>(b, a.library, "eglCreatePbufferSurface");
    a.query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(a.get_proc("eglQueryDevicesEXT"));
    a.get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(a.get_proc("eglGetPlatformDisplayEXT"));
    return a;
  }();
  return api;
}

// One initialized display per process, shared by all EGL contexts and never terminated
// (eglTerminate would pull the display from under every other context).
struct EglDisplay {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = nullptr;
  std::string tried;  // what was tried, for the error message
};

bool try_display(const EglApi& api, EGLDisplay display, const std::string& name, EglDisplay& out) {
  if (display == EGL_NO_DISPLAY) {
    out.tried += name + ": no display; ";
    return false;
  }
  EGLint major = 0;
  EGLint minor = 0;
  if (!api.initialize(display, &major, &minor)) {
    out.tried += name + ": eglInitialize error " + std::to_string(api.get_error()) + "; ";
    return false;
  }
  const EGLint attributes[] = {EGL_RED_SIZE,        8, EGL_GREEN_SIZE,      8,
                               EGL_BLUE_SIZE,       8, EGL_DEPTH_SIZE,      24,
                               EGL_STENCIL_SIZE,    8, EGL_SURFACE_TYPE,    EGL_PBUFFER_BIT,
                               EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,         EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!api.choose_config(display, attributes, &config, 1, &count) || count < 1) {
    out.tried += name + ": no OpenGL config; ";
    return false;
  }
  out.display = display;
  out.config = config;
  return true;
}

const EglDisplay& egl_display() {
  static const EglDisplay shared = [] {
    const EglApi& api = egl_api();
    EglDisplay d;
    // An explicit device (MUJOCO_EGL_DEVICE_ID, as MuJoCo's Python bindings read it), else each.
    if (api.query_devices != nullptr && api.get_platform_display != nullptr) {
      std::array<EGLDeviceEXT, 16> devices{};
      EGLint count = 0;
      api.query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count);
      int first = 0;
      int last = count - 1;
      if (const char* id = std::getenv("MUJOCO_EGL_DEVICE_ID"); id != nullptr && *id != '\0') {
        first = last = std::atoi(id);
        if (first < 0 || first >= count) {
          d.tried += "MUJOCO_EGL_DEVICE_ID=" + std::string(id) + " but " +
                     std::to_string(count) + " devices; ";
          return d;
        }
      }
      for (int i = first; i <= last; ++i) {
        EGLDisplay display = api.get_platform_display(EGL_PLATFORM_DEVICE_EXT,
                                                      devices[static_cast<size_t>(i)], nullptr);
        if (try_display(api, display, "device " + std::to_string(i), d)) return d;
      }
      EGLDisplay surfaceless =
          api.get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (try_display(api, surfaceless, "surfaceless", d)) return d;
    }
    try_display(api, api.get_display(EGL_DEFAULT_DISPLAY), "default display", d);
    return d;
  }();
  return shared;
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    const EglApi& api = egl_api();
    const EglDisplay& d = egl_display();
    if (d.display == EGL_NO_DISPLAY) fail(Backend::kEgl, "no EGL display (" + d.tried + ")");
    display_ = d.display;
    if (!api.bind_api(EGL_OPENGL_API)) fail(Backend::kEgl, "eglBindAPI(EGL_OPENGL_API) failed");
    context_ = api.create_context(display_, d.config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) {
      fail(Backend::kEgl, "eglCreateContext error " + std::to_string(api.get_error()));
    }
    // Surfaceless when the display allows it, else a 1x1 pbuffer.
    const char* extensions = api.query_string(display_, EGL_EXTENSIONS);
    const bool surfaceless = extensions != nullptr &&
                             std::string(extensions).find("EGL_KHR_surfaceless_context") !=
                                 std::string::npos;
    if (!surfaceless) {
      const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      surface_ = api.create_pbuffer(display_, d.config, size);
      if (surface_ == EGL_NO_SURFACE) fail(Backend::kEgl, "eglCreatePbufferSurface failed");
    }
    make_current();
    auto get_string = reinterpret_cast<GlGetStringFn>(api.get_proc("glGetString"));
    gl_renderer_ = gl_string(get_string, kGlRenderer);
    gl_version_ = gl_string(get_string, kGlVersion);
    if (gl_version_.empty()) fail(Backend::kEgl, "glGetString(GL_VERSION) returned nothing");
  }
  ~EglContext() override {
    const EglApi& api = egl_api();
    if (api.get_current() == context_) {
      api.make_current(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    api.destroy_context(display_, context_);
  }
  void make_current() override {
    const EglApi& api = egl_api();
    if (api.get_current() == context_) return;
    if (!api.make_current(display_, surface_, surface_, context_)) {
      fail(Backend::kEgl, "eglMakeCurrent error " + std::to_string(api.get_error()));
    }
  }
  Backend backend() const override { return Backend::kEgl; }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
};

}  // namespace

std::unique_ptr<GlContext> make_gl_context(Backend backend) {
  HRIB_CHECK(backend != Backend::kNone) << "the none back end has no GL context";
  check_platform(backend, false);
  std::unique_ptr<GlContext> context;
  if (backend == Backend::kOsmesa) {
    context = std::make_unique<OsmesaContext>();
  } else {
    context = std::make_unique<EglContext>();
  }
  check_platform(backend, true);
  return context;
}

std::shared_ptr<GlContext> thread_gl_context(Backend backend) {
  thread_local std::shared_ptr<GlContext> context;
  if (!context || context->backend() != backend) context = make_gl_context(backend);
  return context;
}

Backend loaded_gl_platform() {
  std::lock_guard<std::mutex> lock(platform_mutex);
  return platform;
}

}  // namespace hribench::render
