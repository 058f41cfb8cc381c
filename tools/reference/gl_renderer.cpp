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
#include <string>

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
const char* kFragmentShader = R"(#version 450 core
const int kMaxLayers = 8;
uniform int shading;  // 0 layers, 1 deluxe
uniform int lit_diffuse, lit_normal, lit_gloss, lit_glow, lit_lightmap, lit_deluxe;  // layer indices, -1 none
uniform float specular_power, specular_intensity;
in vec3 v_s, v_t, v_n, v_eye;
uniform sampler2D layer_tex[kMaxLayers];
uniform int layer_count;
uniform bool layer_lightmap_coords[kMaxLayers];
uniform bool layer_add[kMaxLayers];
uniform float layer_scale[kMaxLayers];
uniform vec3 layer_xf_s[kMaxLayers];  // s' = a s + b t + c
uniform vec3 layer_xf_t[kMaxLayers];  // t' = d s + e t + f
uniform vec4 colour;
uniform int alpha_func;  // 0 always, 1 greater, 2 less, 3 gequal
uniform float alpha_ref;
uniform bool coverage_only;
in vec2 v_uv;
in vec2 v_lm;
out vec4 frag;
vec4 deluxe_colour() {
  vec4 t[kMaxLayers];
  for (int i = 0; i < layer_count; ++i) {
    vec2 st = layer_lightmap_coords[i] ? v_lm : v_uv;
    st = vec2(dot(layer_xf_s[i], vec3(st, 1.0)), dot(layer_xf_t[i], vec3(st, 1.0)));
    t[i] = texture(layer_tex[i], st);
  }
  vec4 d = t[lit_diffuse];
  vec3 lm_dir = t[lit_deluxe].rgb * 2.0 - 1.0;
  vec3 l = normalize(vec3(dot(lm_dir, v_s), dot(lm_dir, v_t), dot(lm_dir, v_n)));
  vec3 lc = t[lit_lightmap].rgb * (layer_scale[lit_lightmap] / max(0.25, l.z));
  vec3 n = lit_normal >= 0 ? normalize(t[lit_normal].rgb - 0.5) : vec3(0.0, 0.0, 1.0);
  float diffuse = max(dot(n, l), 0.0);
  vec3 rgb = d.rgb * diffuse * lc;
  if (lit_gloss >= 0) {
    vec4 g = t[lit_gloss];
    vec3 h = normalize(l + normalize(v_eye));
    float nh = max(dot(n, h), 0.0);
    float spec = nh > 0.0 ? pow(nh, specular_power * g.a) : 0.0;
    rgb += g.rgb * (specular_intensity * spec) * lc;
  }
  if (lit_glow >= 0) rgb += t[lit_glow].rgb;
  return vec4(rgb, d.a) * colour;
}

void main() {
  vec4 c = vec4(1.0);
  for (int i = 0; i < layer_count && shading == 0; ++i) {
    vec2 st = layer_lightmap_coords[i] ? v_lm : v_uv;
    st = vec2(dot(layer_xf_s[i], vec3(st, 1.0)), dot(layer_xf_t[i], vec3(st, 1.0)));
    vec4 s = texture(layer_tex[i], st);
    if (i == 0) {
      c = vec4(s.rgb * layer_scale[i], s.a) * colour;
    } else if (layer_add[i]) {
      c = vec4(c.rgb + s.rgb * layer_scale[i], c.a * s.a);
    } else {
      c = vec4(c.rgb * (s.rgb * layer_scale[i]), c.a * s.a);
    }
  }
  if (layer_count == 0) c = colour;
  if (shading == 1) c = deluxe_colour();
  if (!coverage_only) {
    if (alpha_func == 1 && !(c.a > alpha_ref)) discard;
    if (alpha_func == 2 && !(c.a < alpha_ref)) discard;
    if (alpha_func == 3 && !(c.a >= alpha_ref)) discard;
  }
  frag = c;
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

}  // namespace

struct GlRenderer::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint program = 0;
  GLint u_shading = -1, u_lit[6] = {-1, -1, -1, -1, -1, -1}, u_specular_power = -1, u_specular_intensity = -1, u_eye = -1;
  GLint u_world = -1, u_clip = -1, u_layer_count = -1, u_colour = -1, u_alpha_func = -1, u_alpha_ref = -1, u_coverage = -1;
  GLint u_layer_lm[kMaxLayers], u_layer_add[kMaxLayers], u_layer_scale[kMaxLayers], u_layer_xf_s[kMaxLayers],
      u_layer_xf_t[kMaxLayers];
};

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

GLenum gl_blend(BlendFactor f) {
  switch (f) {
    case BlendFactor::zero: return GL_ZERO;
    case BlendFactor::one: return GL_ONE;
    case BlendFactor::src_colour: return GL_SRC_COLOR;
    case BlendFactor::one_minus_src_colour: return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::src_alpha: return GL_SRC_ALPHA;
    case BlendFactor::one_minus_src_alpha: return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::dst_colour: return GL_DST_COLOR;
    case BlendFactor::one_minus_dst_colour: return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::dst_alpha: return GL_DST_ALPHA;
    case BlendFactor::one_minus_dst_alpha: return GL_ONE_MINUS_DST_ALPHA;
  }
  return GL_ONE;
}

GLenum gl_depth(DepthFunc f) {
  switch (f) {
    case DepthFunc::less: return GL_LESS;
    case DepthFunc::lequal: return GL_LEQUAL;
    case DepthFunc::equal: return GL_EQUAL;
    case DepthFunc::always: return GL_ALWAYS;
  }
  return GL_LESS;
}

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
void begin_pass(const StereoView& view, Run pass, GLint u_coverage) {
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
  glUniform1i(u_coverage, pass == Run::covered);
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
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  m->program = glCreateProgram();
  glAttachShader(m->program, vs);
  glAttachShader(m->program, fs);
  glLinkProgram(m->program);
  GLint ok = 0;
  glGetProgramiv(m->program, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("reference program does not link");
  glDeleteShader(vs);
  glDeleteShader(fs);
  const GLuint p = m->program;
  glUseProgram(p);
  for (int i = 0; i < kMaxLayers; ++i) {
    // Appended, not "[" + std::to_string(i): GCC 12 warns falsely (-Wrestrict) on that.
    const std::string k = std::string("[").append(std::to_string(i)).append("]");
    glUniform1i(glGetUniformLocation(p, ("layer_tex" + k).c_str()), i);
    m->u_layer_lm[i] = glGetUniformLocation(p, ("layer_lightmap_coords" + k).c_str());
    m->u_layer_add[i] = glGetUniformLocation(p, ("layer_add" + k).c_str());
    m->u_layer_scale[i] = glGetUniformLocation(p, ("layer_scale" + k).c_str());
    m->u_layer_xf_s[i] = glGetUniformLocation(p, ("layer_xf_s" + k).c_str());
    m->u_layer_xf_t[i] = glGetUniformLocation(p, ("layer_xf_t" + k).c_str());
  }
  m->u_world = glGetUniformLocation(p, "world_from_object");
  m->u_clip = glGetUniformLocation(p, "clip_from_world");
  m->u_layer_count = glGetUniformLocation(p, "layer_count");
  m->u_colour = glGetUniformLocation(p, "colour");
  m->u_alpha_func = glGetUniformLocation(p, "alpha_func");
  m->u_alpha_ref = glGetUniformLocation(p, "alpha_ref");
  m->u_coverage = glGetUniformLocation(p, "coverage_only");
  m->u_shading = glGetUniformLocation(p, "shading");
  const char* lit_names[6] = {"lit_diffuse", "lit_normal", "lit_gloss", "lit_glow", "lit_lightmap", "lit_deluxe"};
  for (int k = 0; k < 6; ++k) m->u_lit[k] = glGetUniformLocation(p, lit_names[k]);
  m->u_specular_power = glGetUniformLocation(p, "specular_power");
  m->u_specular_intensity = glGetUniformLocation(p, "specular_intensity");
  m->u_eye = glGetUniformLocation(p, "eye_position");
}

GlRenderer::~GlRenderer() {
  if (m->program) glDeleteProgram(m->program);
  if (m->display != EGL_NO_DISPLAY) {
    eglMakeCurrent(m->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m->context != EGL_NO_CONTEXT) eglDestroyContext(m->display, m->context);
    eglTerminate(m->display);
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
void draw_objects(const GlRenderer::Impl& m, const Scene& scene, int frame, const StereoView& view, const Uploaded& up, int eyes,
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
    glBindVertexArray(up.vao[size_t(obj.mesh)]);
    glUniformMatrix4fv(m.u_world, 1, GL_FALSE, &obj.world_from_object.m[0][0]);
    glUniform1i(m.u_layer_count, GLint(pass.layers.size()));
    for (size_t i = 0; i < pass.layers.size(); ++i) {
      const TextureLayer& l = pass.layers[i];
      const UvTransform xf = l.transform(seconds);
      glUniform1i(m.u_layer_lm[i], l.coords == TexCoords::lightmap);
      glUniform1i(m.u_layer_add[i], l.combine == Combine::add);
      glUniform1f(m.u_layer_scale[i], l.scale);
      glUniform3f(m.u_layer_xf_s[i], xf.a, xf.b, xf.c);
      glUniform3f(m.u_layer_xf_t[i], xf.d, xf.e, xf.f);
      glActiveTexture(GLenum(GL_TEXTURE0 + i));
      glBindTexture(GL_TEXTURE_2D, up.tex[size_t(l.texture)]);
    }
    glUniform4f(m.u_colour, pass.colour.x, pass.colour.y, pass.colour.z, pass.colour.w);
    glUniform1i(m.u_alpha_func, int(pass.alpha_func));
    glUniform1i(m.u_shading, pass.shading == Shading::deluxe ? 1 : 0);
    const LayerKind lit_kinds[6] = {LayerKind::diffuse, LayerKind::normal,   LayerKind::gloss,
                                    LayerKind::glow,    LayerKind::lightmap, LayerKind::deluxe};
    for (int k = 0; k < 6; ++k) glUniform1i(m.u_lit[k], pass.layer(lit_kinds[k]));
    glUniform1f(m.u_specular_power, pass.specular_power);
    glUniform1f(m.u_specular_intensity, pass.specular_intensity);
    glUniform1f(m.u_alpha_ref, pass.alpha_ref);
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
      glUniformMatrix4fv(m.u_clip, 1, GL_FALSE, &view.clip_from_world[e].m[0][0]);
      glUniform3f(m.u_eye, view.eye_position[e].x, view.eye_position[e].y, view.eye_position[e].z);
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
  glUseProgram(m->program);

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
  glFinish();  // uploads done before timing starts
  const auto start = std::chrono::steady_clock::now();
  for (Run pass : {Run::image, Run::passed, Run::covered}) {
    begin_pass(view, pass, m->u_coverage);
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

std::vector<FrameTime> GlRenderer::time(const Scene& scene, const std::vector<int>& frames, const std::vector<StereoView>& views,
                                        int aniso, int repeats) {
  if (frames.size() != views.size()) throw std::runtime_error("time() needs one frame number per view");
  if (views.empty()) return {};
  const Target target(views.front().frame_width, views.front().frame_height);
  const Uploaded up(scene, aniso);
  glUseProgram(m->program);
  GLuint query = 0;
  glGenQueries(1, &query);
  // GPU time of one pass: the frame's draws inside a GL_TIME_ELAPSED query,
  // the clear outside it.
  const auto timed = [&](int frame, const StereoView& view, int eyes, bool tiny) {
    begin_pass(view, Run::image, m->u_coverage);
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
