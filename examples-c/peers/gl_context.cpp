// A headless EGL context (Mesa surfaceless: llvmpipe when there is no GPU) for glcollide's GL
// backends. Links -lEGL; only the benchmark uses it.
#include "common.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

namespace peers {

void *gl_get_proc(void *, const char *name) { return reinterpret_cast<void *>(eglGetProcAddress(name)); }

bool gl_context_init(std::string &renderer) {
    static bool ready = false;
    if (ready) return true;
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!getPlatformDisplay) return false;
    EGLDisplay dpy = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, nullptr, nullptr)) return false;
    if (!eglBindAPI(EGL_OPENGL_API)) return false;
    EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig cfg;
    EGLint n = 0;
    if (!eglChooseConfig(dpy, cfg_attr, &cfg, 1, &n) || n < 1) return false;
    EGLint ctx_attr[] = {EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT) return false;
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) return false;
    typedef const unsigned char *(*GetString)(unsigned);
    auto gs = reinterpret_cast<GetString>(eglGetProcAddress("glGetString"));
    if (gs) {
        const unsigned char *r = gs(0x1F01 /*GL_RENDERER*/);
        const unsigned char *v = gs(0x1F02 /*GL_VERSION*/);
        renderer = std::string(r ? (const char *)r : "?") + ", GL " + (v ? (const char *)v : "?");
    }
    ready = true;
    return true;
}

} // namespace peers
