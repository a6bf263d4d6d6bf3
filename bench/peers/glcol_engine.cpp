// glcollide through its C API (include/glcollide.h), on the CPU backend or a GL backend
// (a headless EGL context on Mesa: llvmpipe when there is no GPU).
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "../../include/glcollide.h"
#include "common.h"

namespace {
void check(GlcolStatus s, const char* what) {
  if (s != GLCOL_STATUS_OK)
    throw std::runtime_error(std::string(what) + ": " + glcol_status_name(s) + ": " + glcol_last_error_message());
}

void* get_proc(void*, const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

bool g_gl = false;

struct GlcolEngine : Engine {
  int backend;
  float eps;
  uint32_t leaf;
  GlcolScene* scene = nullptr;
  GlcolMeshId ia = 0, ib = 0;
  size_t na = 0, nb = 0;
  GlcolEngine(int be, float e, uint32_t l) : backend(be), eps(e), leaf(l) {}
  ~GlcolEngine() override {
    if (scene) glcol_scene_destroy(scene);
  }
  std::string name() const override {
    switch (backend) {
      case GLCOL_BACKEND_GL_SELECT: return "glcollide_gl_select";
      case GLCOL_BACKEND_GL_COMPUTE: return "glcollide_gl_compute";
      default: return "glcollide";
    }
  }
  GlcolMeshId add(const Mesh& m, const std::vector<float>& v) {
    GlcolMeshDesc d;
    glcol_mesh_desc_init(&d);
    d.positions = v.data();
    d.vertex_count = m.nv();
    d.indices = m.t.data();
    d.polygon_count = m.nt();
    d.vertices_per_polygon = 3;
    GlcolMeshId id = 0;
    check(glcol_mesh_create(scene, &d, &id), "glcol_mesh_create");
    return id;
  }
  void build(const Mesh& a, const Mesh& b, const Frame& f) override {
    GlcolSceneDesc d;
    glcol_scene_desc_init(&d);
    d.backend = GlcolBackend(backend);
    d.epsilon = eps;
    d.max_polygons_per_box = leaf;
    if (backend != GLCOL_BACKEND_CPU) {
      if (!g_gl) throw std::runtime_error("no GL context");
      d.get_proc_address = get_proc;
    }
    check(glcol_scene_create(&d, &scene), "glcol_scene_create");
    ia = add(a, f.a);
    ib = add(b, f.b);
    na = a.nv();
    nb = b.nv();
  }
  void update(const Frame& f) override {
    check(glcol_mesh_update_positions(scene, ia, f.a.data(), 0, na, 0), "update a");
    check(glcol_mesh_update_positions(scene, ib, f.b.data(), 0, nb, 0), "update b");
  }
  const GlcolContact* last = nullptr;
  size_t last_n = 0;
  void query_only() { check(glcol_query(scene, ia, &last, &last_n), "glcol_query"); }
  void query(std::vector<Pair>& out) override {
    query_only();
    out.clear();
    for (size_t i = 0; i < last_n; i++) out.push_back({last[i].reference_polygon, last[i].other_polygon});
  }
  // The library has no memory accessor yet: the Rust bench (benches/parry.rs) counts it
  // from the structures; here nothing is claimed.
  size_t bytes() const override { return 0; }
};
}  // namespace

Engine* make_glcol(int backend, float eps, uint32_t leaf) { return new GlcolEngine(backend, eps, leaf); }

bool gl_context_init(std::string& renderer) {
  if (g_gl) return true;
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
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
  typedef const unsigned char* (*GetString)(unsigned);
  auto gs = reinterpret_cast<GetString>(eglGetProcAddress("glGetString"));
  if (gs) {
    const unsigned char* r = gs(0x1F01 /*GL_RENDERER*/);
    const unsigned char* v = gs(0x1F02 /*GL_VERSION*/);
    renderer = std::string(r ? (const char*)r : "?") + ", GL " + (v ? (const char*)v : "?");
  }
  g_gl = true;
  return true;
}
