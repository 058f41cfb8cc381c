// crowd: hundreds of small objects (people) sharing four clothing textures,
// plus lamp posts sharing one metal texture, on a grass field. Many draws,
// few textures, high sharing: the case OO-VR's texture-sharing batching
// (Section 5.1) is built for.
#include <cmath>

#include "oovr/core/rng.h"
#include "oovr/scene/builtin.h"
#include "oovr/scene/builtin/procedural.h"

namespace oovr {
namespace {

using namespace procedural;

Scene make_crowd() {
  SceneBuilder b("crowd", "320 people sharing 4 clothing textures and 12 lamp posts on a grass field, under a sky dome");
  const int t_grass = b.texture(grass(512, 11));
  const int t_metal = b.texture(metal(256, 12));
  const uint8_t shirts[4][3] = {{200, 40, 40}, {40, 90, 200}, {230, 200, 60}, {60, 160, 80}};
  int person_mat[4];
  for (int i = 0; i < 4; ++i) {
    person_mat[i] =
        b.material(Material::textured("person-" + std::to_string(i),
                                      b.texture(fabric_person(256, 20 + uint64_t(i), shirts[i][0], shirts[i][1], shirts[i][2]))));
  }
  const int mat_grass = b.material(Material::textured("grass", t_grass));
  const int mat_lamp = b.material(Material::textured("lamp", t_metal));

  b.object("field", b.mesh(grid(40, 40, 24, 24, 16, 16)), mat_grass, Mat4::identity());

  // A person: body (cylinder, texture rows 0..0.7) and head (sphere, rows 0.7..1).
  Mesh person = cylinder(0.22f, 1.45f, 10, 3, 1, 0.7f, true);
  Mesh head = sphere(0.13f, 10, 6, 1, 1);
  for (auto& v : head.vertices) v.uv.y = 0.7f + 0.3f * v.uv.y;
  append(person, head, translate({0, 1.6f, 0}));
  person.name = "person";
  const int person_mesh = b.mesh(person);

  Rng rng(2024);
  int n = 0;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 20; ++i) {
      const float x = -14.0f + 1.45f * float(i) + rng.uniform(-0.4f, 0.4f);
      const float z = -14.0f + 1.7f * float(j) + rng.uniform(-0.4f, 0.4f);
      const float s = rng.uniform(0.85f, 1.1f);
      const Mat4 t = translate({x, 0, z}) * rotate({0, 1, 0}, rng.uniform(0.0f, 2 * kPi)) * scale({s, s, s});
      b.object("person-" + std::to_string(n++), person_mesh, person_mat[rng.below(4)], t);
    }

  Mesh lamp = cylinder(0.08f, 4.0f, 8, 2, 1, 4, false);
  append(lamp, sphere(0.25f, 12, 8), translate({0, 4.2f, 0}));
  lamp.name = "lamp";
  const int lamp_mesh = b.mesh(lamp);
  for (int i = 0; i < 12; ++i) {
    const float x = (i % 2 ? 17.0f : -17.0f), z = -16.0f + 3.0f * float(i / 2) * 1.9f;
    b.object("lamp-" + std::to_string(i), lamp_mesh, mat_lamp, translate({x, 0, z}));
  }

  b.object("sky", b.mesh(dome(80.0f, 48, 12)), b.material(Material::textured("sky", b.texture(sky(512, 13)))), Mat4::identity());

  // Camera: a slow walk along the crowd's edge at head height, looking across it.
  CameraPath& cam = b.scene().camera;
  cam.fov_y_degrees = 90.0f;
  cam.z_near = 0.05f;
  cam.z_far = 150.0f;
  const int frames = 120;
  for (int f = 0; f < frames; ++f) {
    const float t = float(f) / float(frames);
    CameraPose pose;
    pose.position = {-12.0f + 24.0f * t, 2.2f, 16.5f};
    pose.target = {-6.0f + 12.0f * t + 3.0f * std::sin(t * 2 * kPi), 0.8f, 0.0f};
    cam.frames.push_back(pose);
  }
  return b.take();
}

const BuiltinScenes::Add reg("crowd", {"many small objects: 320 people sharing 4 textures, lamp posts", make_crowd});

}  // namespace
}  // namespace oovr
