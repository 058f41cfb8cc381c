#include "gl_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <string>

#include "gl_enums.h"
#include "oovr/experiments/hardware.h"

namespace oovr::reference {

namespace {

// Vertex stage: the world position is computed once and projected for the
// eye, in the same order as oovr's pipeline (pipeline/renderer.cpp).
const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in vec2 lm_uv;
layout(location = 3) in vec3 frame_s;  // tangent frame, for per-pixel lit passes
layout(location = 4) in vec3 frame_t;
layout(location = 5) in vec3 frame_n;
uniform mat4 world_from_object;
uniform mat4 clip_from_world;
uniform vec3 eye_position;
out vec2 v_uv;
out vec2 v_lm;
out vec3 v_s, v_t, v_n, v_eye;
void main() {
  vec4 world = world_from_object * vec4(position, 1.0);
  gl_Position = clip_from_world * vec4(world.xyz, 1.0);
  v_uv = uv;
  v_lm = lm_uv;
  // DarkPlaces' vertex shader: the frame and the eye's direction in it.
  v_s = mat3(world_from_object) * frame_s;
  v_t = mat3(world_from_object) * frame_t;
  v_n = mat3(world_from_object) * frame_n;
  vec3 eye = eye_position - world.xyz;
  v_eye = vec3(dot(eye, v_s), dot(eye, v_t), dot(eye, v_n));
}
)";

// Fragment stage: a pass's layers combined in order (scene/material.h):
// the first texel (RGB x its scale) times the pass colour, then each later
// layer modulates (RGB x scale, alpha) or adds (RGB x scale; alpha
// modulates); then the alpha function. Layer coordinates go through the
// layer's affine transform (tcMod) per fragment, as oovr's pipeline does.
// A deluxe pass (shading 1) samples every layer first, then lights the
// fragment as scene/material.h writes out (DarkPlaces'
// MODE_LIGHTDIRECTIONMAP_MODELSPACE).
//
// One program per kind of pass (its layers' coordinates and combines, the
// shading, which layers light it, the alpha test), as a game's renderer and
// a driver's state-specialised shaders have it: the pass's structure is
// constant in the code and its numbers are uniforms. Only alpha-tested
// passes can discard, so the others keep the early depth test, and no loop
// indexes samplers at run time; a single program for every pass made
// llvmpipe 3 to 10 times slower (docs/performance.md).
const char* kFragmentHead = R"(#version 450 core
const int kMaxLayers = 8;
uniform float specular_power, specular_intensity;
in vec3 v_s, v_t, v_n, v_eye;
uniform sampler2D layer_tex[kMaxLayers];
uniform float layer_scale[kMaxLayers];
uniform vec3 layer_xf_s[kMaxLayers];  // s' = a s + b t + c
uniform vec3 layer_xf_t[kMaxLayers];  // t' = d s + e t + f
uniform vec4 colour;
uniform float alpha_ref;
in vec2 v_uv;
in vec2 v_lm;
out vec4 frag;
vec4 sample_layer(int i, vec2 st) {
  st = vec2(dot(layer_xf_s[i], vec3(st, 1.0)), dot(layer_xf_t[i], vec3(st, 1.0)));
  return texture(layer_tex[i], st);
}
)";

constexpr int kMaxLayers = 8;

GLuint compile(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("reference shader does not compile: ") + log);
  }
  return s;
}

// The fragment shader of one kind of pass; `coverage`: the coverage run's
// (nothing discarded).
std::string fragment_shader(const Pass& pass, bool coverage) {
  const auto idx = [](int i) { return std::to_string(i); };
  const auto coords = [&](size_t i) { return pass.layers[i].coords == TexCoords::lightmap ? "v_lm" : "v_uv"; };
  std::string body;
  const int n = int(pass.layers.size());
  if (pass.shading == Shading::deluxe) {
    const auto lit = [&](LayerKind k) { return pass.layer(k); };
    for (int i = 0; i < n; ++i) body += "  vec4 t" + idx(i) + " = sample_layer(" + idx(i) + ", " + coords(size_t(i)) + ");\n";
    const int diffuse = lit(LayerKind::diffuse), deluxe = lit(LayerKind::deluxe), lightmap = lit(LayerKind::lightmap);
    if (diffuse < 0 || deluxe < 0 || lightmap < 0)
      throw std::runtime_error("a deluxe pass without its diffuse, lightmap or deluxe layer");
    body += "  vec4 d = t" + idx(diffuse) + ";\n";
    body += "  vec3 lm_dir = t" + idx(deluxe) + ".rgb * 2.0 - 1.0;\n";
    body += "  vec3 l = normalize(vec3(dot(lm_dir, v_s), dot(lm_dir, v_t), dot(lm_dir, v_n)));\n";
    body += "  vec3 lc = t" + idx(lightmap) + ".rgb * (layer_scale[" + idx(lightmap) + "] / max(0.25, l.z));\n";
    const int normal = lit(LayerKind::normal);
    body += normal >= 0 ? "  vec3 n = normalize(t" + idx(normal) + ".rgb - 0.5);\n" : "  vec3 n = vec3(0.0, 0.0, 1.0);\n";
    body += "  float diffuse = max(dot(n, l), 0.0);\n  vec3 rgb = d.rgb * diffuse * lc;\n";
    if (const int gloss = lit(LayerKind::gloss); gloss >= 0)
      body += "  vec4 g = t" + idx(gloss) +
              ";\n  vec3 h = normalize(l + normalize(v_eye));\n  float nh = max(dot(n, h), 0.0);\n"
              "  float spec = nh > 0.0 ? pow(nh, specular_power * g.a) : 0.0;\n"
              "  rgb += g.rgb * (specular_intensity * spec) * lc;\n";
    if (const int glow = lit(LayerKind::glow); glow >= 0) body += "  rgb += t" + idx(glow) + ".rgb;\n";
    body += "  vec4 c = vec4(rgb, d.a) * colour;\n";
  } else if (n == 0) {
    body += "  vec4 c = colour;\n";
  } else {
    body += "  vec4 c;\n";
    for (const TextureLayer& l : pass.layers)
      if (l.combine == Combine::fetch || l.combine == Combine::replace)
        throw std::runtime_error(
            "a layer the reference does not combine (a captured game's): it draws built-in scenes and levels");
    for (int i = 0; i < n; ++i) {
      const std::string k = idx(i), t = std::string("s").append(k);  // appended: GCC 12 warns falsely on "s" + string
      body += "  vec4 " + t + " = sample_layer(" + k + ", " + coords(size_t(i)) + ");\n";
      if (i == 0) body += "  c = vec4(" + t + ".rgb * layer_scale[0], " + t + ".a) * colour;\n";
      else if (pass.layers[size_t(i)].combine == Combine::add)
        body += "  c = vec4(c.rgb + " + t + ".rgb * layer_scale[" + k + "], c.a * " + t + ".a);\n";
      else body += "  c = vec4(c.rgb * (" + t + ".rgb * layer_scale[" + k + "]), c.a * " + t + ".a);\n";
    }
  }
  if (!coverage) {
    switch (pass.alpha_func) {
      case AlphaFunc::always: break;
      case AlphaFunc::greater: body += "  if (!(c.a > alpha_ref)) discard;\n"; break;
      case AlphaFunc::less: body += "  if (!(c.a < alpha_ref)) discard;\n"; break;
      case AlphaFunc::gequal: body += "  if (!(c.a >= alpha_ref)) discard;\n"; break;
    }
  }
  return std::string(kFragmentHead) + "void main() {\n" + body + "  frag = c;\n}\n";
}

}  // namespace

// A linked program for one kind of pass and its uniforms' locations (-1:
// not in this program).
struct Program {
  GLuint id = 0;
  GLint u_world = -1, u_clip = -1, u_eye = -1, u_colour = -1, u_alpha_ref = -1;
  GLint u_specular_power = -1, u_specular_intensity = -1;
  GLint u_layer_scale[kMaxLayers], u_layer_xf_s[kMaxLayers], u_layer_xf_t[kMaxLayers];
};

struct GlRenderer::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint vertex_shader = 0;
  // By the fragment shader's text: a kind of pass's program, made on first use.
  std::map<std::string, Program> programs;
  ~Impl() {
    for (auto& [k, p] : programs) glDeleteProgram(p.id);
    if (vertex_shader) glDeleteShader(vertex_shader);
  }
  const Program& program(const Pass& pass, bool coverage);
};

const Program& GlRenderer::Impl::program(const Pass& pass, bool coverage) {
  if (pass.layers.size() > size_t(kMaxLayers))
    throw std::runtime_error("a pass of more than " + std::to_string(kMaxLayers) + " layers");
  std::string text = fragment_shader(pass, coverage);
  const auto it = programs.find(text);
  if (it != programs.end()) return it->second;
  const GLuint fs = compile(GL_FRAGMENT_SHADER, text.c_str());
  Program pr;
  pr.id = glCreateProgram();
  glAttachShader(pr.id, vertex_shader);
  glAttachShader(pr.id, fs);
  glLinkProgram(pr.id);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(pr.id, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("reference program does not link");
  const GLuint p = pr.id;
  glUseProgram(p);
  for (int i = 0; i < kMaxLayers; ++i) {
    // Appended, not "[" + std::to_string(i): GCC 12 warns falsely (-Wrestrict) on that.
    const std::string k = std::string("[").append(std::to_string(i)).append("]");
    glUniform1i(glGetUniformLocation(p, ("layer_tex" + k).c_str()), i);
    pr.u_layer_scale[i] = glGetUniformLocation(p, ("layer_scale" + k).c_str());
    pr.u_layer_xf_s[i] = glGetUniformLocation(p, ("layer_xf_s" + k).c_str());
    pr.u_layer_xf_t[i] = glGetUniformLocation(p, ("layer_xf_t" + k).c_str());
  }
  pr.u_world = glGetUniformLocation(p, "world_from_object");
  pr.u_clip = glGetUniformLocation(p, "clip_from_world");
  pr.u_eye = glGetUniformLocation(p, "eye_position");
  pr.u_colour = glGetUniformLocation(p, "colour");
  pr.u_alpha_ref = glGetUniformLocation(p, "alpha_ref");
  pr.u_specular_power = glGetUniformLocation(p, "specular_power");
  pr.u_specular_intensity = glGetUniformLocation(p, "specular_intensity");
  return programs.emplace(std::move(text), pr).first->second;
}

namespace {

// A display on the first EGL device that is not Mesa's software renderer
// (a GPU), or EGL_NO_DISPLAY.
EGLDisplay hardware_display(PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display) {
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (!query_devices || !query_string) return EGL_NO_DISPLAY;
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!query_devices(16, devices, &count)) return EGL_NO_DISPLAY;
  for (EGLint i = 0; i < count; ++i) {
    const char* ext = query_string(devices[i], EGL_EXTENSIONS);
    if (ext && std::strstr(ext, "EGL_MESA_device_software")) continue;
    EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    EGLint major = 0, minor = 0;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) return d;
  }
  return EGL_NO_DISPLAY;
}

// Everything a scene needs on the GPU: textures (every level as oovr built
// it), one vertex array per mesh.
struct Uploaded {
  std::vector<GLuint> tex, vao, buf;
  Uploaded(const Scene& scene, int aniso) {
    tex.resize(scene.textures.size());
    glGenTextures(GLsizei(tex.size()), tex.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (size_t i = 0; i < scene.textures.size(); ++i) {
      const Texture& t = scene.textures[i];
      glBindTexture(GL_TEXTURE_2D, tex[i]);
      const int levels = t.mipmapped ? int(t.levels.size()) : 1;
      for (int l = 0; l < levels; ++l) {
        const MipLevel& ml = t.levels[size_t(l)];
        glTexImage2D(GL_TEXTURE_2D, l, GL_RGBA8, ml.width, ml.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, ml.rgba.data());
      }
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, t.mipmapped ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      const GLint wrap = t.wrap == Wrap::repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
      glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY, float(aniso));
    }
    vao.resize(scene.meshes.size());
    buf.resize(scene.meshes.size() * 3);
    glGenVertexArrays(GLsizei(vao.size()), vao.data());
    glGenBuffers(GLsizei(buf.size()), buf.data());
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
      const Mesh& mesh = scene.meshes[i];
      glBindVertexArray(vao[i]);
      glBindBuffer(GL_ARRAY_BUFFER, buf[3 * i]);
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(Vertex)), mesh.vertices.data(), GL_STATIC_DRAW);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buf[3 * i + 1]);
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(),
                   GL_STATIC_DRAW);
      glEnableVertexAttribArray(0);
      glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, position)));
      glEnableVertexAttribArray(1);
      glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, uv)));
      glEnableVertexAttribArray(2);
      glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, lm_uv)));
      if (!mesh.frames.empty()) {
        glBindBuffer(GL_ARRAY_BUFFER, buf[3 * i + 2]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.frames.size() * sizeof(TangentFrame)), mesh.frames.data(), GL_STATIC_DRAW);
        const size_t offsets[3] = {offsetof(TangentFrame, s), offsetof(TangentFrame, t), offsetof(TangentFrame, n)};
        for (GLuint k = 0; k < 3; ++k) {
          glEnableVertexAttribArray(3 + k);
          glVertexAttribPointer(3 + k, 3, GL_FLOAT, GL_FALSE, sizeof(TangentFrame), reinterpret_cast<void*>(offsets[k]));
        }
      }
    }
  }
  ~Uploaded() {
    glDeleteBuffers(GLsizei(buf.size()), buf.data());
    glDeleteVertexArrays(GLsizei(vao.size()), vao.data());
    glDeleteTextures(GLsizei(tex.size()), tex.data());
  }
  Uploaded(const Uploaded&) = delete;
  Uploaded& operator=(const Uploaded&) = delete;
};

// A colour + 32-bit float depth framebuffer, bound while it lives.
struct Target {
  GLuint fbo = 0, rb[2] = {0, 0};
  Target(int w, int h) {
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("reference framebuffer incomplete");
  }
  ~Target() {
    glDeleteRenderbuffers(2, rb);
    glDeleteFramebuffers(1, &fbo);
  }
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;
};

// The three runs of a frame: the image, its per-draw passed fragments, and
// per-draw coverage.
enum class Run { image, passed, covered };
// Whether draws set their pass's blend and depth state, or keep the
// coverage run's (depth test always passes, nothing written).
enum class DrawState { pass, coverage };

void apply_pass_state(const oovr::Pass& pass) {
  if (pass.blended()) {
    glEnable(GL_BLEND);
    glBlendFunc(gl_blend(pass.src), gl_blend(pass.dst));
  } else {
    glDisable(GL_BLEND);
  }
  glDepthFunc(gl_depth(pass.depth_func));
  glDepthMask(pass.depth_write ? GL_TRUE : GL_FALSE);
}

// Clears the frame and sets the depth test of a run.
void begin_pass(const StereoView& view, Run pass) {
  glScissor(0, 0, view.frame_width, view.frame_height);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDepthFunc(pass == Run::covered ? GL_ALWAYS : GL_LESS);
  glDepthMask(pass == Run::covered ? GL_FALSE : GL_TRUE);
  if (pass == Run::covered) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
}

}  // namespace

GlRenderer::GlRenderer(Platform platform) : m(std::make_unique<Impl>()) {
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Unavailable("EGL has no eglGetPlatformDisplayEXT");
  if (platform == Platform::any) m->display = hardware_display(get_platform_display);
  if (m->display == EGL_NO_DISPLAY) {
    // Ask Mesa for llvmpipe explicitly, whatever hardware the machine has.
    setenv("GALLIUM_DRIVER", "llvmpipe", 0);
    setenv("EGL_PLATFORM", "surfaceless", 0);
    m->display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (m->display == EGL_NO_DISPLAY) throw Unavailable("EGL surfaceless platform unavailable (is libegl-mesa0 installed?)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(m->display, &major, &minor)) throw Unavailable("eglInitialize failed on the surfaceless platform");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) throw Unavailable("EGL cannot bind the OpenGL API");
  const EGLint attribs[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  m->context = eglCreateContext(m->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  if (m->context == EGL_NO_CONTEXT) throw Unavailable("cannot create an OpenGL 4.5 core context");
  if (!eglMakeCurrent(m->display, EGL_NO_SURFACE, EGL_NO_SURFACE, m->context))
    throw Unavailable("eglMakeCurrent without a surface failed");
  m->vertex_shader = compile(GL_VERTEX_SHADER, kVertexShader);
}

GlRenderer::~GlRenderer() {
  const EGLDisplay display = m->display;
  const EGLContext context = m->context;
  m.reset();  // its programs, while the context is current
  if (display != EGL_NO_DISPLAY) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
  }
}

std::string GlRenderer::renderer_name() const {
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return r ? r : "unknown";
}

namespace {

// Issues every object's draw, in scene order, once per eye in `eyes` (bit
// e: eye e) into that eye's viewport (or a 1x1 scissor at its corner);
// `around(draw, begin)` brackets each draw (draw = object * 2 + eye).
void draw_objects(GlRenderer::Impl& m, const Scene& scene, int frame, const StereoView& view, const Uploaded& up, int eyes,
                  bool tiny_scissor, DrawState state, const std::function<void(size_t draw, bool begin)>& around) {
  glEnable(GL_SCISSOR_TEST);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  const double seconds = scene.camera.seconds(frame);
  for (size_t o = 0; o < scene.objects.size(); ++o) {
    const Object& obj = scene.objects[o];
    const Material& mat = scene.materials[size_t(obj.material)];
    const Pass& pass = scene.pass_of(obj);
    if (pass.layers.size() > size_t(kMaxLayers))
      throw std::runtime_error("material '" + mat.name + "' has a pass of more than " + std::to_string(kMaxLayers) + " layers");
    const Program& pr = m.program(pass, state == DrawState::coverage);
    glUseProgram(pr.id);
    glBindVertexArray(up.vao[size_t(obj.mesh)]);
    glUniformMatrix4fv(pr.u_world, 1, GL_FALSE, &obj.world_from_object.m[0][0]);
    for (size_t i = 0; i < pass.layers.size(); ++i) {
      const TextureLayer& l = pass.layers[i];
      const UvTransform xf = l.transform(seconds);
      glUniform1f(pr.u_layer_scale[i], l.scale);
      glUniform3f(pr.u_layer_xf_s[i], xf.a, xf.b, xf.c);
      glUniform3f(pr.u_layer_xf_t[i], xf.d, xf.e, xf.f);
      glActiveTexture(GLenum(GL_TEXTURE0 + i));
      glBindTexture(GL_TEXTURE_2D, up.tex[size_t(l.texture)]);
    }
    glUniform4f(pr.u_colour, pass.colour.x, pass.colour.y, pass.colour.z, pass.colour.w);
    glUniform1f(pr.u_specular_power, pass.specular_power);
    glUniform1f(pr.u_specular_intensity, pass.specular_intensity);
    glUniform1f(pr.u_alpha_ref, pass.alpha_ref);
    if (mat.two_sided) glDisable(GL_CULL_FACE);
    else glEnable(GL_CULL_FACE);
    if (state == DrawState::pass) apply_pass_state(pass);
    const GLsizei count = GLsizei(scene.meshes[size_t(obj.mesh)].indices.size());
    for (int e = 0; e < view.eyes; ++e) {
      if (!(eyes & (1 << e))) continue;
      const Viewport& vp = view.viewport[e];
      glViewport(vp.x, vp.y, vp.width, vp.height);
      if (tiny_scissor) glScissor(vp.x, vp.y, 1, 1);
      else glScissor(vp.x, vp.y, vp.width, vp.height);
      glUniformMatrix4fv(pr.u_clip, 1, GL_FALSE, &view.clip_from_world[e].m[0][0]);
      glUniform3f(pr.u_eye, view.eye_position[e].x, view.eye_position[e].y, view.eye_position[e].z);
      if (around) around(o * 2 + size_t(e), true);
      glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
      if (around) around(o * 2 + size_t(e), false);
    }
  }
}

}  // namespace

GlFrame GlRenderer::render(const Scene& scene, int frame, const StereoView& view) {
  const int W = view.frame_width, H = view.frame_height;
  const Target target(W, H);
  const Uploaded up(scene, 1);  // the comparison samples isotropically

  GlFrame out;
  out.counts.resize(scene.objects.size() * 2);
  std::vector<GLuint> queries(scene.objects.size() * 2 * 2);
  glGenQueries(GLsizei(queries.size()), queries.data());
  // The image pass runs without queries and is timed. The passed pass
  // renders it again with a GL_SAMPLES_PASSED query per draw (fragments
  // that passed the alpha and depth tests); the covered pass counts every
  // draw's coverage (depth test always passes, no discard, no writes). Each
  // query's result is read right after its draw: with thousands of queries
  // outstanding, llvmpipe (Mesa 22.3) was seen to report counts of other
  // draws, e.g. samples passed for a draw that covered nothing.
  std::vector<GLuint64> results(queries.size(), 0);
  // An untimed image pass first: llvmpipe compiles its shader variants on
  // first use, which the timing should not include.
  begin_pass(view, Run::image);
  draw_objects(*m, scene, frame, view, up, 3, false, DrawState::pass, {});
  glFinish();  // uploads and compiles done before timing starts
  const auto start = std::chrono::steady_clock::now();
  for (Run pass : {Run::image, Run::passed, Run::covered}) {
    begin_pass(view, pass);
    std::function<void(size_t, bool)> around;
    if (pass != Run::image)
      around = [&](size_t draw, bool begin) {
        const size_t q = draw * 2 + (pass == Run::covered ? 1 : 0);
        if (begin) {
          glBeginQuery(GL_SAMPLES_PASSED, queries[q]);
        } else {
          glEndQuery(GL_SAMPLES_PASSED);
          glGetQueryObjectui64v(queries[q], GL_QUERY_RESULT, &results[q]);
        }
      };
    draw_objects(*m, scene, frame, view, up, 3, false, pass == Run::covered ? DrawState::coverage : DrawState::pass, around);
    if (pass == Run::image) {
      out.colour = Image(W, H);
      glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, out.colour.rgba.data());
      out.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
  }
  for (size_t i = 0; i < out.counts.size(); ++i) out.counts[i] = {results[i * 2 + 1], results[i * 2]};
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw std::runtime_error("OpenGL error " + std::to_string(err) + " in the reference renderer");
  glDeleteQueries(GLsizei(queries.size()), queries.data());
  return out;
}

double GlRenderer::draw_seconds(const Scene& scene, const std::vector<int>& frames, const std::vector<StereoView>& views,
                                int aniso) {
  if (frames.size() != views.size()) throw std::runtime_error("draw_seconds() needs one frame number per view");
  if (views.empty()) return 0;
  const int W = views.front().frame_width, H = views.front().frame_height;
  const Target target(W, H);
  const Uploaded up(scene, aniso);
  std::vector<uint8_t> pixels(size_t(W) * size_t(H) * 4);
  glFinish();  // uploads done before the clock starts
  const auto start = std::chrono::steady_clock::now();
  for (size_t k = 0; k < views.size(); ++k) {
    if (views[k].frame_width != W || views[k].frame_height != H)
      throw std::runtime_error("every drawn view must have the same size");
    begin_pass(views[k], Run::image);
    draw_objects(*m, scene, frames[k], views[k], up, 3, false, DrawState::pass, {});
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw std::runtime_error("OpenGL error " + std::to_string(err) + " while drawing");
  return seconds;
}

std::vector<FrameTime> GlRenderer::time(const Scene& scene, const std::vector<int>& frames, const std::vector<StereoView>& views,
                                        int aniso, int repeats) {
  if (frames.size() != views.size()) throw std::runtime_error("time() needs one frame number per view");
  if (views.empty()) return {};
  const Target target(views.front().frame_width, views.front().frame_height);
  const Uploaded up(scene, aniso);
  GLuint query = 0;
  glGenQueries(1, &query);
  // GPU time of one pass: the frame's draws inside a GL_TIME_ELAPSED query,
  // the clear outside it.
  const auto timed = [&](int frame, const StereoView& view, int eyes, bool tiny) {
    begin_pass(view, Run::image);
    glFinish();
    glBeginQuery(GL_TIME_ELAPSED, query);
    draw_objects(*m, scene, frame, view, up, eyes, tiny, DrawState::pass, {});
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-3;
  };
  std::vector<FrameTime> out;
  for (size_t k = 0; k < views.size(); ++k) {
    const StereoView& view = views[k];
    if (view.frame_width != views.front().frame_width || view.frame_height != views.front().frame_height)
      throw std::runtime_error("every timed view must have the same size");
    std::vector<double> full, geom, left;
    for (int rep = -1; rep < repeats; ++rep) {  // one warm-up
      const double f = timed(frames[k], view, 3, false), g = timed(frames[k], view, 3, true),
                   l = timed(frames[k], view, 1, false);
      if (rep < 0) continue;
      full.push_back(f);
      geom.push_back(g);
      left.push_back(l);
    }
    out.push_back({median(full), median(geom), median(left)});
  }
  glDeleteQueries(1, &query);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw std::runtime_error("OpenGL error " + std::to_string(err) + " while timing");
  return out;
}

}  // namespace oovr::reference
