// Writes seed corpora for the fuzzers: the synthetic BSP and SGI files of
// the tests (tests/game_data.h), shader scripts in the styles OpenArena and
// Nexuiz write them, the configuration presets, a real trace and cache
// entry, small PLY / GLB / glTF / OBJ / AC3D files of each form the
// readers know (and assimp's own test models of those formats, where
// installed), TORCS files, the sweep files and a run record. Usage: oovr-fuzz-seeds
// DIR [SOURCE_DIR]
#include <zip.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "apitrace_writer.h"
#include "collect_job.h"
#include "game_data.h"
#include "oovr/experiments/sweep.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/pipeline/trace_cache.h"
#include "oovr/scene/builtin.h"
#include "oovr/scene/formats/gl_trace.h"
#include "oovr/scene/scene_codec.h"

namespace fs = std::filesystem;

static void write(const fs::path& p, const std::vector<uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: oovr-fuzz-seeds DIR [SOURCE_DIR]\n");
    return 2;
  }
  const fs::path dir = argv[1];
  for (const char* sub :
       {"config", "trace", "model", "ac3d", "torcs", "pk3", "sweep", "hardware", "collect", "sweep_name", "apitrace"})
    fs::create_directories(dir / sub);
  // apitrace files (fuzz_apitrace): a frame of a GL 1.x game as its event
  // stream (first byte 0: put into snappy chunks by the target) and as a
  // whole file (first byte 1).
  {
    oovr::test::TraceWriter w;
    w.gl_viewport(64, 48);
    w.gl_texture_2x2(1, std::vector<uint8_t>(16, 200));
    w.call("glEnable", {{"cap", w.e("GL_TEXTURE_2D", 0x0DE1)}});
    w.call("glEnableClientState", {{"array", w.e("GL_VERTEX_ARRAY", 0x8074)}});
    const std::vector<float> xyz = {-1, -1, -5, 1, -1, -5, 1, 1, -5};
    const std::vector<uint32_t> idx = {0, 1, 2};
    w.gl_client_array("glVertexPointer", 3, "GL_FLOAT", 0x1406, xyz);
    w.call("glDrawElements", {{"mode", w.e("GL_TRIANGLES", 4)},
                              {"count", w.i(3)},
                              {"type", w.e("GL_UNSIGNED_INT", 0x1405)},
                              {"indices", w.blob(idx)}});
    w.call("glBegin", {{"mode", w.e("GL_QUADS", 7)}});
    for (int k = 0; k < 4; ++k) w.call("glVertex2f", {{"x", w.f(float(k & 1))}, {"y", w.f(float(k >> 1))}});
    w.call("glEnd", {});
    w.call("glXSwapBuffers", {{"dpy", w.opaque(1)}, {"drawable", w.u(2)}});
    std::string stream = std::string(1, '\0') + w.stream();
    std::string file = std::string(1, '\1') + w.finish();
    write(dir / "apitrace" / "stream", std::vector<uint8_t>(stream.begin(), stream.end()));
    write(dir / "apitrace" / "file", std::vector<uint8_t>(file.begin(), file.end()));
    // An OpenGL 3 frame in DarkPlaces' manner: a lightmapped permutation
    // drawn into a framebuffer object's texture, a generic one copying it
    // into the window.
    oovr::test::TraceWriter g3;
    g3.gl_viewport(64, 48);
    g3.gl_texture_2x2(7, std::vector<uint8_t>(16, 200));
    g3.call("glBindFramebuffer", {{"target", g3.e("GL_FRAMEBUFFER", 0x8D40)}, {"framebuffer", g3.u(3)}});
    g3.call("glFramebufferTexture2D", {{"target", g3.e("GL_FRAMEBUFFER", 0x8D40)},
                                       {"attachment", g3.e("GL_COLOR_ATTACHMENT0", 0x8CE0)},
                                       {"textarget", g3.e("GL_TEXTURE_2D", 0x0DE1)},
                                       {"texture", g3.u(9)},
                                       {"level", g3.i(0)}});
    g3.gl_program(5, {"MODE_LIGHTMAP", "USEGLOW"});
    g3.gl_uniform_matrix({1, 0, 0, 0, 0, 1.333f, 0, 0, 0, 0, -1.02f, -1, 0, 0, -2.02f, 0});
    g3.call("glUniform1i", {{"location", g3.i(2)}, {"v0", g3.i(0)}});
    g3.call("glUniform3f", {{"location", g3.i(3)}, {"v0", g3.f(1)}, {"v1", g3.f(0.5f)}, {"v2", g3.f(1)}});
    g3.gl_buffer_quad(-5);
    g3.call("glBindFramebuffer", {{"target", g3.e("GL_FRAMEBUFFER", 0x8D40)}, {"framebuffer", g3.u(0)}});
    g3.gl_program(6, {"MODE_POSTPROCESS", "USEVIEWTINT"});
    g3.gl_uniform_matrix({2.0f / 64, 0, 0, 0, 0, -2.0f / 48, 0, 0, 0, 0, -1, 0, -1, 1, 0, 1});
    g3.call("glBindTexture", {{"target", g3.e("GL_TEXTURE_2D", 0x0DE1)}, {"texture", g3.u(9)}});
    g3.gl_buffer_quad(0);
    g3.call("glXSwapBuffers", {{"dpy", g3.opaque(1)}, {"drawable", g3.u(2)}});
    std::string gl3_stream = std::string(1, '\0') + g3.stream();
    std::string gl3_file = std::string(1, '\1') + g3.finish();
    write(dir / "apitrace" / "gl3_stream", std::vector<uint8_t>(gl3_stream.begin(), gl3_stream.end()));
    write(dir / "apitrace" / "gl3_file", std::vector<uint8_t>(gl3_file.begin(), gl3_file.end()));
    // An OpenGL 3 frame in ioquake3's opengl2 manner: two vertex array
    // objects, a lit lightmapped program with key frames and a generic one
    // with texture-coordinate mods.
    oovr::test::TraceWriter q3;
    q3.gl_viewport(64, 48);
    q3.gl_texture_2x2(7, std::vector<uint8_t>(16, 200));
    q3.gl_ioq3_program(5, "lightall", {"USE_LIGHT", "USE_FAST_LIGHT", "USE_LIGHTMAP", "USE_VERTEX_ANIMATION"});
    q3.gl_uniform_matrix({1, 0, 0, 0, 0, 1.333f, 0, 0, 0, 0, -1.02f, -1, 0, 0, -2.02f, 0});
    q3.gl_uniform4f(4, 2, 2, 2, 1);
    q3.call("glUniform1f", {{"location", q3.i(6)}, {"v0", q3.f(0.5f)}});
    q3.call("glBindVertexArray", {{"array", q3.u(1)}});
    q3.gl_buffer_quad(-5);
    q3.gl_ioq3_program(6, "generic", {"USE_TCGEN", "USE_TCMOD", "USE_RGBAGEN"});
    q3.gl_uniform_matrix({1, 0, 0, 0, 0, 1.333f, 0, 0, 0, 0, -1.02f, -1, 0, 0, -2.02f, 0});
    q3.call("glUniform1i", {{"location", q3.i(5)}, {"v0", q3.i(1)}});
    q3.call("glBindVertexArray", {{"array", q3.u(2)}});
    q3.gl_buffer_quad(-6);
    q3.call("glXSwapBuffers", {{"dpy", q3.opaque(1)}, {"drawable", q3.u(2)}});
    std::string q3_stream = std::string(1, '\0') + q3.stream();
    std::string q3_file = std::string(1, '\1') + q3.finish();
    write(dir / "apitrace" / "ioq3_stream", std::vector<uint8_t>(q3_stream.begin(), q3_stream.end()));
    write(dir / "apitrace" / "ioq3_file", std::vector<uint8_t>(q3_file.begin(), q3_file.end()));
    // The same frame imported, as a cached import (fuzz_trace reads its
    // input as one too).
    oovr::GlTraceWindow window;
    window.count = 1;
    const std::string scene = oovr::encode_scene(oovr::import_gl_trace_bytes(w.finish(), "seed.trace", window));
    write(dir / "trace" / "scene", std::vector<uint8_t>(scene.begin(), scene.end()));
  }
  // Hardware data: the first lines of the shipped H100 file and the tests' one.
  if (argc == 3)
    for (const char* f : {"docs/data/hardware/h100-gl-frames.csv", "tests/data/hardware-one-point.csv"}) {
      std::ifstream in(fs::path(argv[2]) / f);
      std::ofstream out(dir / "hardware" / fs::path(f).filename());
      std::string line;
      for (int n = 0; n < 12 && std::getline(in, line); ++n) out << line << '\n';
    }
  // pk3: a stored and a deflated entry, as the games' archives hold them.
  {
    int err = 0;
    zip_t* z = zip_open((dir / "pk3" / "pak0.pk3").c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    static const std::string shader = "textures/a/b\n{\n\t{\n\t\tmap textures/a/b.tga\n\t}\n}\n";
    static const std::string lump(300, 'x');
    const zip_int64_t i = zip_file_add(z, "scripts/a.shader", zip_source_buffer(z, shader.data(), shader.size(), 0), 0);
    zip_set_file_compression(z, zip_uint64_t(i), ZIP_CM_STORE, 0);
    zip_file_add(z, "maps/m.bsp", zip_source_buffer(z, lump.data(), lump.size(), 0), 0);
    zip_close(z);
  }
  // Configuration: the presets, and keys of every kind.
  if (argc == 3)
    for (const auto& e : fs::directory_iterator(fs::path(argv[2]) / "configs"))
      if (e.path().extension() == ".toml")
        fs::copy_file(e.path(), dir / "config" / e.path().filename(), fs::copy_options::overwrite_existing);
  std::ofstream(dir / "config" / "kinds.toml") << "gpms = 8\n[link]\nbandwidth = \"128GBps\"\nlatency = \"32ns\"\n"
                                                  "[cache.l2]\nsize = \"2MB\"\nways = 16\n[oo]\ntsl_threshold = 0.5\n"
                                                  "prealloc = false\n[gpm]\ndraw_cycles = 625.5\n";
  // Sweeps (first byte 0): the project's sweep files and one of every key;
  // run records (first byte 1): a real one, as a SLURM task writes it.
  if (argc == 3)
    for (const auto& e : fs::directory_iterator(fs::path(argv[2]) / "experiments"))
      if (e.path().extension() == ".toml" && e.path().filename() != "paper-claims.toml") {
        std::ifstream in(e.path(), std::ios::binary);
        std::ofstream(dir / "sweep" / e.path().filename(), std::ios::binary) << '\0' << in.rdbuf();
      }
  std::ofstream(dir / "sweep" / "keys.toml", std::ios::binary)
      << '\0'
      << "name = \"k\"\nimages = true\nscenes = [\"crowd\"]\nschemes = [\"baseline\", \"afr\"]\n"
         "resolutions = [\"64x48\"]\nframe = [0, 1]\nframes = 4\naniso = 2\n[set]\ngpms = 4\n[sweep.link]\n"
         "bandwidth = [\"32GBps\", 1000000000]\n[[point]]\nscheme = \"object\"\nsweep = {}\nset = { \"oo.split\" = false }\n";
  {
    oovr::Sweep s =
        oovr::parse_sweep("scenes = ['crowd']\nschemes = ['oo-vr']\nresolutions = ['64x48']\nimages = true\n", "s", "");
    oovr::resolve_all(s);
    oovr::SweepRunOptions o;
    o.use_cache = false;
    o.on_record = [&](const oovr::RunRecord& r) {
      std::ofstream(dir / "sweep" / "record.json", std::ios::binary) << '\1' << oovr::to_json(r).dump();
    };
    oovr::run_points(s, {0}, o);
  }
  // --collect (fuzz_collect): the task file of fuzz_collect's job, its
  // lines as a task writes them, whole, cut short, and one forged.
  {
    oovr::Sweep s = oovr::parse_sweep(kCollectSweep, "c.toml", "");
    oovr::resolve_all(s);
    std::string lines;
    oovr::SweepRunOptions o;
    o.use_cache = false;
    o.on_record = [&](const oovr::RunRecord& r) { lines += oovr::to_json(r).dump() + "\n"; };
    oovr::run_points(s, {0, 1}, o);
    std::ofstream(dir / "collect" / "task.jsonl", std::ios::binary) << lines;
    std::ofstream(dir / "collect" / "cut.jsonl", std::ios::binary) << lines.substr(0, lines.size() * 2 / 3);
    std::string forged = lines.substr(0, lines.find('\n') + 1);
    const size_t id = forged.find("\"id\":\"");
    if (id != std::string::npos) forged.replace(id + 6, 16, "\"><script>x</sc");
    std::ofstream(dir / "collect" / "forged.jsonl", std::ios::binary) << forged;
  }
  // Sweep names (fuzz_sweep_name).
  for (const char* name : {"paper", "quick-2.v1_x", "x\ntouch PWNED\n#", "<img src=x>", "../up",
                           "\xc2\x9b"
                           "31m"})
    std::ofstream(dir / "sweep_name" / ("name-" + std::to_string(std::hash<std::string>{}(name) % 100000)), std::ios::binary)
        << name;
  // A trace of a small frame: its payload and its cache entry.
  {
    const oovr::Scene scene = oovr::BuiltinScenes::find("crowd")->make();
    oovr::StereoRig rig;
    rig.eye_width = 48;
    rig.eye_height = 32;
    const oovr::StereoView view = oovr::make_stereo_view(scene.camera, 0, rig);
    const oovr::FrameTrace t = oovr::render_frame(scene, view, oovr::PipelineSettings{}, 0).trace;
    const std::string payload = oovr::serialize_trace(t), entry = oovr::encode_entry("0123456789abcdef", t);
    std::ofstream(dir / "trace" / "payload.bin", std::ios::binary) << payload;
    std::ofstream(dir / "trace" / "entry.bin", std::ios::binary) << entry;
  }
  // Models: the first byte picks the format (0 PLY, 1 GLB, 2 glTF, 3 OBJ, 4 AC3D).
  std::ofstream(dir / "model" / "ascii.ply", std::ios::binary)
      << '\0'
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  {
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    ply.append(36, '\0');
    ply += char(3);
    for (int i = 0; i < 3; ++i) ply.append(std::string(1, char(i)) + std::string(3, '\0'));
    std::ofstream(dir / "model" / "binary.ply", std::ios::binary) << '\0' << ply;
  }
  {
    const std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":8}],"accessors":[{"count":2}]})";
    std::string glb = "glTF";
    const auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + 8));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    glb += json;
    u32(8);
    u32(0x004E4942u);
    glb.append(8, '\0');
    std::ofstream(dir / "model" / "box.glb", std::ios::binary) << '\1' << glb;
    std::ofstream(dir / "model" / "box.gltf", std::ios::binary)
        << '\2'
        << R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":3,"uri":"data:application/octet-stream;base64,AAAA"}],"accessors":[{"count":1}]})";
  }
  // Models again: a one-triangle glTF with a skin, an animation and a
  // morph target (taken out before assimp reads it), OBJ with groups and a
  // material library, AC3D (4).
  std::ofstream(dir / "model" / "skin.gltf", std::ios::binary)
      << '\2'
      << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"skin":0,"children":[1]},{"mesh":0}],)"
         R"("skins":[{"joints":[0]}],"animations":[{"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}}],)"
         R"("samplers":[{"input":0,"output":0}]}],"meshes":[{"weights":[1],"primitives":[{"attributes":{"POSITION":0},)"
         R"("targets":[{"POSITION":0}]}]}],"buffers":[{"byteLength":36,)"
         R"("uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],)"
         R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";
  // A triangle strip and a fan, indexed, of four vertices: the modes whose
  // short forms assimp 5.2 misread (formats/model_checks.cpp).
  for (const char* mode : {"5", "6"})
    std::ofstream(dir / "model" / (std::string("mode") + mode + ".gltf"), std::ios::binary)
        << '\2'
        << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":)"
        << mode
        << R"(}]}],"buffers":[{"byteLength":64,"uri":"data:application/octet-stream;base64,)"
           R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPwAAgD8AAAAAAAAAAAEAAAACAAAAAwAAAA=="}],)"
           R"("bufferViews":[{"buffer":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":16}],)"
           R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
           R"({"bufferView":1,"componentType":5125,"count":4,"type":"SCALAR"}]})";
  std::ofstream(dir / "model" / "groups.obj", std::ios::binary)
      << '\3'
      << "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
         "o a\ng left\nusemtl red\nf 1/1/1 2/2/1 3/3/1\ng right\nusemtl blue\nf 2 4 3 1\nl 1 2\np 3\n";
  std::ofstream(dir / "model" / "quad.ac", std::ios::binary)
      << '\4'
      << "AC3Db\nMATERIAL \"m\" rgb 1 1 1 amb 0.2 0.2 0.2 emis 0 0 0 spec 0 0 0 shi 0 trans 0\n"
         "OBJECT world\nkids 1\nOBJECT poly\nname \"quad\"\nnumvert 4\n0 0 0\n1 0 0\n1 0 1\n0 0 1\nnumsurf 1\n"
         "SURF 0x10\nmat 0\nrefs 4\n0 0 0\n1 1 0\n2 1 1\n3 0 1\nkids 0\n";
  {
    // assimp's test models (Debian's assimp-testmodels) of the formats
    // oovr reads through it, up to the fuzzers' 64 KB.
    const std::pair<const char*, char> kFormats[] = {{".ply", 0}, {".glb", 1}, {".gltf", 2}, {".obj", 3}, {".ac", 4}};
    std::error_code ec;
    int n = 0;
    for (fs::recursive_directory_iterator it("/usr/share/assimp/models", ec), end; !ec && it != end; it.increment(ec)) {
      if (!it->is_regular_file(ec) || it->file_size(ec) > 65535) continue;
      std::string ext = it->path().extension().string();
      for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
      for (const auto& [e, prefix] : kFormats)
        if (ext == e) {
          std::ifstream in(it->path(), std::ios::binary);
          std::ofstream(dir / "model" / ("assimp-" + std::to_string(n++) + ext), std::ios::binary) << prefix << in.rdbuf();
        }
    }
  }
  // AC3D: a textured quad in a group, as TORCS writes them.
  std::ofstream(dir / "ac3d" / "quad.ac")
      << "AC3Db\nMATERIAL \"m\" rgb 1 1 1 amb 0.2 0.2 0.2 emis 0 0 0 spec 0 0 0 shi 0 trans 0\n"
         "OBJECT world\nkids 1\nOBJECT group\nkids 1\nOBJECT poly\nname \"quad\"\n"
         "texture \"road.png\"\nnumvert 4\n0 0 0\n1 0 0\n1 0 1\n0 0 1\nnumsurf 1\n"
         "SURF 0x10\nmat 0\nrefs 4\n0 0 0\n1 1 0\n2 1 1\n3 0 1\nkids 0\n";
  // TORCS: an oval in both generations of the format.
  const std::string oval = R"(<section name="s1"><attstr name="type" val="str"/><attnum name="lg" unit="m" val="100"/></section>
      <section name="t1"><attstr name="type" val="lft"/><attnum name="radius" unit="m" val="50"/><attnum name="arc" unit="deg" val="180"/>
      <attstr name="profil" val="linear"/><attnum name="end radius" val="60"/><attnum name="profil steps" val="4"/></section>
      <section name="t2"><attstr name="type" val="rgt"/><attnum name="radius" unit="m" val="50"/><attnum name="arc" unit="deg" val="180"/></section>)";
  std::ofstream(dir / "torcs" / "v4.xml") << R"(<params name="oval"><section name="Main Track"><attnum name="width" val="10"/>
    <section name="Right Side"><attnum name="width" val="4"/></section><section name="Left Border"><attnum name="width" val="1"/></section>
    <section name="Track Segments">)" << oval
                                          << "</section></section></params>";
  std::ofstream(dir / "torcs" / "v3.xml") << R"(<params name="oval"><section name="Main Track"><attnum name="width" val="10"/>
    <attnum name="rside width" val="4"/><attnum name="lborder width" val="1"/><attnum name="profil steps length" val="8"/>
    <section name="segments">)" << oval << "</section></section></params>";
  fs::create_directories(dir / "bsp");
  fs::create_directories(dir / "sgi");
  fs::create_directories(dir / "shader");
  write(dir / "bsp" / "test.bsp", oovr::test::make_test_bsp());
  for (int channels = 1; channels <= 4; ++channels)
    for (bool rle : {false, true})
      write(dir / "sgi" / ("test-" + std::to_string(channels) + (rle ? "-rle" : "") + ".rgb"),
            oovr::test::make_test_sgi(11, 6, channels, rle));
  // Every stage keyword oovr reads, in the forms the games use.
  std::ofstream(dir / "shader" / "stages.shader") << R"(textures/base/wall
{
  qer_editorimage textures/base/wall.tga
  cull none
  sort additive
  {
    map textures/base/wall.tga
    rgbGen identity
    tcMod scale 2 2
    tcMod scroll 0.1 -0.5
  }
  {
    map $lightmap
    blendFunc GL_DST_COLOR GL_ZERO
    tcGen lightmap
  }
  {
    clampmap textures/base/glow.jpg
    blendFunc add
    alphaFunc GE128
    depthWrite
    depthFunc equal
    rgbGen const ( 0.5 0.25 1 )
    alphaGen const 0.5
    detail
  }
  {
    animMap 10 textures/a.tga textures/b.tga
    blendfunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA
    tcMod rotate 30
    tcGen environment
  }
}
textures/sky/space
{
  surfaceparm sky
  surfaceparm nolightmap
  skyParms env/space - -
  { map textures/sky/clouds.tga blendFunc filter }
}
textures/fog/red
{
  fogparms ( 1 0 0 ) 128
  surfaceparm nodraw
}
)";
  std::ofstream(dir / "shader" / "nexuiz.shader") << R"(textures/eX/eX_q2_01
{
	qer_EditorImage textures/eX/eX_q2_01.tga
	{
		map textures/eX/eX_q2_01
	}
	{
		map $lightmap
	}
}
)";
  return 0;
}
