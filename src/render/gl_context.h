#pragma once
// Headless OpenGL contexts for MuJoCo's renderer: OSMesa (CPU) and EGL (GPU, or Mesa's
// software device where there is no GPU).
//
// Why the libraries are dlopen()ed, not linked: MuJoCo 2.2.2 finds GL functions with its own
// glad loader, which first looks for `eglGetProcAddress`, then `OSMesaGetProcAddress`, then
// `glXGetProcAddressARB` in the process's GLOBAL symbol table. A binary linked against both
// libEGL and libOSMesa therefore resolves GL through EGL even when the current context is
// OSMesa, and mjr_makeContext fails ("gladLoadGL error"). We load exactly one platform library
// with RTLD_LOCAL; glad then finds it by walking the loaded libraries (dl_iterate_phdr).
// The loader runs once per process, so a process uses ONE GL platform: asking for the other
// one afterwards is an error (core::InputError), not a silent wrong-driver render.
//
// A GlContext is current on at most one thread at a time; make_current() binds it to the
// calling thread. Not copyable.

#include <memory>
#include <string>
#include <string_view>

namespace hribench::render {

// The GL platform a context is made with. `kNone` never touches GL.
enum class Backend { kOsmesa, kEgl, kNone };

// "osmesa", "egl", "none".
std::string_view to_string(Backend backend);
// Parses "osmesa" | "egl" | "none"; throws core::InputError(where, ...) on anything else.
Backend parse_backend(std::string_view text, std::string_view where = "--backend");

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread (no-op when it already is).
  virtual void make_current() = 0;
  virtual Backend backend() const = 0;
  // GL_RENDERER / GL_VERSION of this context, read once at creation (provenance).
  const std::string& gl_renderer() const { return gl_renderer_; }
  const std::string& gl_version() const { return gl_version_; }

 protected:
  GlContext() = default;
  std::string gl_renderer_;
  std::string gl_version_;
};

// Creates a context of `backend` (kOsmesa or kEgl) and makes it current on the calling thread.
// Throws core::InputError starting "no usable GL context" when the platform library is missing,
// no display/device/context can be made, or this process already loaded the other platform.
std::unique_ptr<GlContext> make_gl_context(Backend backend);

// The calling thread's context of `backend`: made (make_gl_context) on the thread's first call
// and kept until the thread ends, so that renderers made one after another on a worker thread
// (one per episode) share one context and llvmpipe's compiled shaders instead of making and
// compiling their own (docs/rendering.md). Every renderer sharing it must be used on this
// thread only. Throws as make_gl_context.
std::shared_ptr<GlContext> thread_gl_context(Backend backend);

// The GL platform this process has loaded (kNone while no GL context was ever made).
Backend loaded_gl_platform();

}  // namespace hribench::render
