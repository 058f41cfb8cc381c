#include "fixed_function.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstddef>
#include <stdexcept>

#include "gl_enums.h"
#include "gl_renderer.h"
#include "oovr/core/error.h"
#include "oovr/scene/stereo.h"

namespace oovr::reference {

namespace {

constexpr int kUnits = 2;  // what the OpenGL 1.x games of docs/real-frames.md use

bool identity_transform(const TextureLayer& l) { return l.mods.empty(); }

std::string pass_refusal(const Pass& p) {
  if (p.shading != Shading::layers) return "per-pixel lighting (a deluxe pass), which needs a shader";
  if (p.layers.size() > size_t(kUnits)) return "a pass of " + std::to_string(p.layers.size()) + " layers (two units here)";
  for (size_t i = 0; i < p.layers.size(); ++i) {
    const TextureLayer& l = p.layers[i];
    if (!identity_transform(l)) return "texture coordinates moved by tcMod (a texture matrix)";
    if (l.combine == Combine::fetch) return "a layer sampled and not combined";
    if (l.scale != 1.0f && l.scale != 2.0f && l.scale != 4.0f)
      return "a layer scale of " + std::to_string(l.scale) + " (GL_RGB_SCALE takes 1, 2 or 4)";
    if (l.combine == Combine::add && (i == 0 || l.scale != 1.0f)) return "an added layer first or scaled";
    if (l.combine == Combine::replace && (i != 0 || l.scale != 1.0f)) return "a replacing layer after the first or scaled";
  }
  return "";
}

// Unit `u`'s texture environment for layer `l`: MODULATE, ADD and REPLACE
// as they are; a scaled modulation through GL_ARB_texture_env_combine
// (previous x texel x GL_RGB_SCALE, alpha modulated), as DarkPlaces and
// Quake 3's overbright lightmaps without hardware gamma do.
void set_environment(int u, const TextureLayer& l) {
  if (l.combine == Combine::replace) {
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
  } else if (l.combine == Combine::add) {
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_ADD);
  } else if (l.scale == 1.0f) {
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
  } else {
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    const GLint previous = u == 0 ? GL_PRIMARY_COLOR : GL_PREVIOUS;
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_MODULATE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_RGB, GL_TEXTURE);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, previous);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_MODULATE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_ALPHA, GL_TEXTURE);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_ALPHA, previous);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_ALPHA, GL_SRC_ALPHA);
    glTexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, l.scale);
    glTexEnvf(GL_TEXTURE_ENV, GL_ALPHA_SCALE, 1.0f);
  }
}

// The EGL display, pbuffer and compatibility context, current while it lives.
struct Context {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLSurface surface = EGL_NO_SURFACE;
  EGLContext context = EGL_NO_CONTEXT;
  Context(int w, int h) {
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) throw Unavailable("EGL has no eglGetPlatformDisplayEXT");
    setenv("GALLIUM_DRIVER", "llvmpipe", 0);
    display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
      throw Unavailable("EGL surfaceless platform unavailable (is libegl-mesa0 installed?)");
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE,
                                     EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_ALPHA_SIZE,
                                     8,
                                     EGL_DEPTH_SIZE,
                                     24,
                                     EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, config_attribs, &config, 1, &configs) || configs < 1)
      throw Unavailable("no EGL configuration with an RGBA8 pbuffer and a 24-bit depth buffer");
    const EGLint surface_attribs[] = {EGL_WIDTH, w, EGL_HEIGHT, h, EGL_NONE};
    surface = eglCreatePbufferSurface(display, config, surface_attribs);
    if (surface == EGL_NO_SURFACE) throw Unavailable("cannot create a pbuffer surface");
    if (!eglBindAPI(EGL_OPENGL_API)) throw Unavailable("EGL cannot bind the OpenGL API");
    // No version asked: a compatibility context, where OpenGL 1.x lives.
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
    if (context == EGL_NO_CONTEXT) throw Unavailable("cannot create an OpenGL compatibility context");
    if (!eglMakeCurrent(display, surface, surface, context)) throw Unavailable("eglMakeCurrent on the pbuffer failed");
  }
  ~Context() {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    if (display != EGL_NO_DISPLAY) eglTerminate(display);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

}  // namespace

std::string fixed_function_refusal(const Scene& scene) {
  if (scene.captured()) return "it is a captured game";
  for (const Object& o : scene.objects) {
    if (o.view != DrawView::world) return "object '" + o.name + "' is not placed in the world";
    if (!scene.meshes[size_t(o.mesh)].colours.empty()) return "mesh of object '" + o.name + "' has vertex colours";
    const std::string why = pass_refusal(scene.pass_of(o));
    if (!why.empty()) return "material '" + scene.materials[size_t(o.material)].name + "' has " + why;
  }
  return "";
}

Image draw_fixed_function(const Scene& scene, const FixedFunctionRun& run) {
  if (const std::string why = fixed_function_refusal(scene); !why.empty())
    throw Error("scene '" + scene.name + "' cannot be drawn through OpenGL 1.x's fixed function: " + why);
  const int path = int(scene.camera.frames.size());
  if (run.first_frame < 0 || run.frames < 1 || run.first_frame + run.frames > path)
    throw Error("frames " + std::to_string(run.first_frame) + " to " + std::to_string(run.first_frame + run.frames - 1) +
                " are not all on the camera path of " + std::to_string(path) + " frames");
  const Context context(run.width, run.height);

  // Textures as a game uploads them: every level, its filters and wrap.
  std::vector<GLuint> tex(scene.textures.size());
  if (!tex.empty()) glGenTextures(GLsizei(tex.size()), tex.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& t = scene.textures[i];
    glBindTexture(GL_TEXTURE_2D, tex[i]);
    const size_t levels = t.mipmapped ? t.levels.size() : 1;
    for (size_t l = 0; l < levels; ++l)
      glTexImage2D(GL_TEXTURE_2D, GLint(l), GL_RGBA8, t.levels[l].width, t.levels[l].height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   t.levels[l].rgba.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, t.mipmapped ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    const GLint wrap = t.wrap == Wrap::repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  }

  StereoRig rig;  // one view: the window, no eye offset
  rig.ipd_m = 0;
  rig.eye_width = run.width;
  rig.eye_height = run.height;
  glViewport(0, 0, run.width, run.height);
  glEnable(GL_DEPTH_TEST);
  glFrontFace(GL_CCW);
  glEnableClientState(GL_VERTEX_ARRAY);
  Image img(run.width, run.height);
  for (int f = run.first_frame; f < run.first_frame + run.frames; ++f) {
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(0, 0, 0, 1);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const EyeCamera cam = eye_camera(scene.camera, f, rig, kLeft);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(&cam.clip_from_eye.m[0][0]);
    glMatrixMode(GL_MODELVIEW);
    for (const Object& o : scene.draws(f)) {
      const Material& mat = scene.materials[size_t(o.material)];
      const Pass& pass = scene.pass_of(o);
      const Mesh& mesh = scene.meshes[size_t(o.mesh)];
      const Mat4 modelview = cam.eye_from_world * o.world_from_object;
      glLoadMatrixf(&modelview.m[0][0]);
      glVertexPointer(3, GL_FLOAT, sizeof(Vertex), &mesh.vertices[0].position);
      for (int u = 0; u < kUnits; ++u) {
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        glClientActiveTexture(GLenum(GL_TEXTURE0 + u));
        if (size_t(u) >= pass.layers.size()) {
          glDisable(GL_TEXTURE_2D);
          glDisableClientState(GL_TEXTURE_COORD_ARRAY);
          continue;
        }
        const TextureLayer& l = pass.layers[size_t(u)];
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, tex[size_t(l.texture)]);
        set_environment(u, l);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(2, GL_FLOAT, sizeof(Vertex),
                          l.coords == TexCoords::lightmap ? &mesh.vertices[0].lm_uv : &mesh.vertices[0].uv);
      }
      glColor4f(pass.colour.x, pass.colour.y, pass.colour.z, pass.colour.w);
      if (pass.blended()) {
        glEnable(GL_BLEND);
        glBlendFunc(gl_blend(pass.src), gl_blend(pass.dst));
      } else {
        glDisable(GL_BLEND);
      }
      if (pass.alpha_func != AlphaFunc::always) {
        glEnable(GL_ALPHA_TEST);
        glAlphaFunc(gl_alpha(pass.alpha_func), pass.alpha_ref);
      } else {
        glDisable(GL_ALPHA_TEST);
      }
      glDepthFunc(gl_depth(pass.depth_func));
      glDepthMask(pass.depth_write ? GL_TRUE : GL_FALSE);
      const GLboolean c = pass.colour_write ? GL_TRUE : GL_FALSE;
      glColorMask(c, c, c, c);
      if (pass.offset_factor != 0 || pass.offset_units != 0) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(pass.offset_factor, pass.offset_units);
      } else {
        glDisable(GL_POLYGON_OFFSET_FILL);
      }
      if (mat.two_sided) {
        glDisable(GL_CULL_FACE);
      } else {
        glEnable(GL_CULL_FACE);
        glCullFace(mat.cull_front ? GL_FRONT : GL_BACK);
      }
      glDrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT, mesh.indices.data());
    }
    if (f == run.first_frame + run.frames - 1)
      glReadPixels(0, 0, run.width, run.height, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
    eglSwapBuffers(context.display, context.surface);
  }
  const GLenum err = glGetError();
  if (!tex.empty()) glDeleteTextures(GLsizei(tex.size()), tex.data());
  if (err != GL_NO_ERROR) throw Error("OpenGL error " + std::to_string(err) + " drawing the fixed-function frames");
  return img;
}

}  // namespace oovr::reference
