#include "gl_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <chrono>
#include <cstdlib>
#include <string>

namespace oovr::reference {

namespace {

// Vertex stage: the world position is computed once and projected for the
// eye, in the same order as oovr's pipeline (pipeline/renderer.cpp).
const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in vec2 lm_uv;
uniform mat4 world_from_object;
uniform mat4 clip_from_world;
out vec2 v_uv;
out vec2 v_lm;
void main() {
  vec4 world = world_from_object * vec4(position, 1.0);
  gl_Position = clip_from_world * vec4(world.xyz, 1.0);
  v_uv = uv;
  v_lm = lm_uv;
}
)";

// Fragment stage: texture x colour x (lightmap x scale); alpha test.
const char* kFragmentShader = R"(#version 450 core
uniform sampler2D diffuse_tex;
uniform sampler2D lightmap_tex;
uniform bool has_diffuse;
uniform bool has_lightmap;
uniform vec4 colour;
uniform float lightmap_scale;
uniform bool alpha_test;
uniform float alpha_cutoff;
uniform bool coverage_only;
in vec2 v_uv;
in vec2 v_lm;
out vec4 frag;
void main() {
  vec4 c = has_diffuse ? texture(diffuse_tex, v_uv) : vec4(1.0);
  c *= colour;
  if (has_lightmap) c.rgb *= texture(lightmap_tex, v_lm).rgb * lightmap_scale;
  if (alpha_test && !coverage_only && c.a < alpha_cutoff) discard;
  frag = c;
}
)";

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
};

GlRenderer::GlRenderer() : m(std::make_unique<Impl>()) {
  // Ask Mesa for llvmpipe explicitly, whatever hardware the machine has.
  setenv("GALLIUM_DRIVER", "llvmpipe", 0);
  setenv("EGL_PLATFORM", "surfaceless", 0);
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Unavailable("EGL has no eglGetPlatformDisplayEXT");
  m->display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (m->display == EGL_NO_DISPLAY) throw Unavailable("EGL surfaceless platform unavailable (is libegl-mesa0 installed?)");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(m->display, &major, &minor)) throw Unavailable("eglInitialize failed on the surfaceless platform");
  if (!eglBindAPI(EGL_OPENGL_API)) throw Unavailable("EGL cannot bind the OpenGL API");
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
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

GlFrame GlRenderer::render(const Scene& scene, const StereoView& view) {
  const int W = view.frame_width, H = view.frame_height;
  GLuint fbo = 0, rb[2] = {0, 0};
  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(2, rb);
  glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, W, H);
  glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("reference framebuffer incomplete");

  // Textures: every level exactly as oovr built it.
  std::vector<GLuint> tex(scene.textures.size());
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
    glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY, 1.0f);
  }

  // Meshes: one vertex array each, laid out as oovr's Vertex.
  std::vector<GLuint> vao(scene.meshes.size()), buf(scene.meshes.size() * 2);
  glGenVertexArrays(GLsizei(vao.size()), vao.data());
  glGenBuffers(GLsizei(buf.size()), buf.data());
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i];
    glBindVertexArray(vao[i]);
    glBindBuffer(GL_ARRAY_BUFFER, buf[2 * i]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(Vertex)), mesh.vertices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buf[2 * i + 1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, uv)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, lm_uv)));
  }

  const GLuint p = m->program;
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "diffuse_tex"), 0);
  glUniform1i(glGetUniformLocation(p, "lightmap_tex"), 1);
  const GLint u_world = glGetUniformLocation(p, "world_from_object");
  const GLint u_clip = glGetUniformLocation(p, "clip_from_world");
  const GLint u_has_diffuse = glGetUniformLocation(p, "has_diffuse");
  const GLint u_has_lightmap = glGetUniformLocation(p, "has_lightmap");
  const GLint u_colour = glGetUniformLocation(p, "colour");
  const GLint u_lm_scale = glGetUniformLocation(p, "lightmap_scale");
  const GLint u_alpha_test = glGetUniformLocation(p, "alpha_test");
  const GLint u_cutoff = glGetUniformLocation(p, "alpha_cutoff");
  const GLint u_coverage = glGetUniformLocation(p, "coverage_only");

  GlFrame out;
  out.counts.resize(scene.objects.size() * 2);
  std::vector<GLuint> queries(scene.objects.size() * 2 * 2);
  glGenQueries(GLsizei(queries.size()), queries.data());

  glEnable(GL_SCISSOR_TEST);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  // Pass 0 renders the image without queries and is timed. Pass 1 renders
  // it again with a GL_SAMPLES_PASSED query per draw (fragments that passed
  // the alpha and depth tests); pass 2 counts every draw's coverage (depth
  // test always passes, no discard, no writes). Each query's result is read
  // right after its draw: with thousands of queries outstanding, llvmpipe
  // (Mesa 22.3) was seen to report counts of other draws, e.g. samples
  // passed for a draw that covered nothing.
  enum Pass { kTimed = 0, kPassed = 1, kCovered = 2 };
  std::vector<GLuint64> results(queries.size(), 0);
  glFinish();  // uploads done before timing starts
  const auto start = std::chrono::steady_clock::now();
  for (int pass = kTimed; pass <= kCovered; ++pass) {
    glScissor(0, 0, W, H);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(0, 0, 0, 1);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(pass == kCovered ? GL_ALWAYS : GL_LESS);
    glDepthMask(pass == kCovered ? GL_FALSE : GL_TRUE);
    if (pass == kCovered) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUniform1i(u_coverage, pass == kCovered);
    for (size_t o = 0; o < scene.objects.size(); ++o) {
      const Object& obj = scene.objects[o];
      const Material& mat = scene.materials[size_t(obj.material)];
      glBindVertexArray(vao[size_t(obj.mesh)]);
      glUniformMatrix4fv(u_world, 1, GL_FALSE, &obj.world_from_object.m[0][0]);
      glUniform1i(u_has_diffuse, mat.diffuse >= 0);
      glUniform1i(u_has_lightmap, mat.lightmap >= 0);
      glUniform4f(u_colour, mat.colour.x, mat.colour.y, mat.colour.z, mat.colour.w);
      glUniform1f(u_lm_scale, mat.lightmap_scale);
      glUniform1i(u_alpha_test, mat.alpha_test);
      glUniform1f(u_cutoff, mat.alpha_cutoff);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, mat.diffuse >= 0 ? tex[size_t(mat.diffuse)] : 0);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, mat.lightmap >= 0 ? tex[size_t(mat.lightmap)] : 0);
      if (mat.two_sided) glDisable(GL_CULL_FACE);
      else glEnable(GL_CULL_FACE);
      const GLsizei count = GLsizei(scene.meshes[size_t(obj.mesh)].indices.size());
      for (int e = 0; e < view.eyes; ++e) {
        const Viewport& vp = view.viewport[e];
        glViewport(vp.x, vp.y, vp.width, vp.height);
        glScissor(vp.x, vp.y, vp.width, vp.height);
        glUniformMatrix4fv(u_clip, 1, GL_FALSE, &view.clip_from_world[e].m[0][0]);
        if (pass == kTimed) {
          glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
          continue;
        }
        const size_t q = (o * 2 + size_t(e)) * 2 + size_t(pass - kPassed);
        glBeginQuery(GL_SAMPLES_PASSED, queries[q]);
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
        glEndQuery(GL_SAMPLES_PASSED);
        glGetQueryObjectui64v(queries[q], GL_QUERY_RESULT, &results[q]);
      }
    }
    if (pass == kTimed) {
      out.colour = Image(W, H);
      glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, out.colour.rgba.data());
      out.render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
  }
  for (size_t i = 0; i < out.counts.size(); ++i) out.counts[i] = {results[i * 2 + 1], results[i * 2]};
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw std::runtime_error("OpenGL error " + std::to_string(err) + " in the reference renderer");

  glDeleteQueries(GLsizei(queries.size()), queries.data());
  glDeleteBuffers(GLsizei(buf.size()), buf.data());
  glDeleteVertexArrays(GLsizei(vao.size()), vao.data());
  glDeleteTextures(GLsizei(tex.size()), tex.data());
  glDeleteRenderbuffers(2, rb);
  glDeleteFramebuffers(1, &fbo);
  return out;
}

}  // namespace oovr::reference
