// OO_Application, the object-oriented VR programming model (paper
// Section 5.1): an application declares objects, each rendered as one
// multi-view task with two viewports (viewportL, viewportR) so that the SMP
// engine of one GPM renders both views from the same data. The auto-model
// derives viewportR by shifting the original viewport along X. An object may
// have to follow others (the programmer's order), which OO_Middleware keeps.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "oovr/scene/scene.h"
#include "oovr/scene/stereo.h"

namespace oovr {

struct OOObject {
  uint32_t draw = 0;            // the draw call (scene object) it renders
  Viewport viewport[2];         // viewportL, viewportR
  std::vector<uint32_t> after;  // objects (ids) it must follow; all smaller than its own
  uint64_t triangles = 0;       // triangles of its mesh (known to the application)
  uint64_t vertices = 0;        // vertices of its mesh
  // The textures it samples, with their sizes in bytes (every mip level).
  std::vector<std::pair<uint32_t, uint64_t>> textures;
};

class OOApplication {
 public:
  // An object with both viewports given (GL_OVR_multiview2 style). Returns its id.
  // `frame`: the camera frame whose draws `draw` indexes (Scene::draws).
  uint32_t add_object(const Scene& scene, uint32_t draw, Viewport left, Viewport right, int frame = 0);
  // The auto-model: viewportR is `viewport` shifted right by its width.
  uint32_t add_object_auto(const Scene& scene, uint32_t draw, Viewport viewport, int frame = 0);
  // `object` must follow `earlier` (an object added before it).
  void add_dependency(uint32_t object, uint32_t earlier);

  const std::vector<OOObject>& objects() const { return m_objects; }

 private:
  std::vector<OOObject> m_objects;
};

// A scene as an OO application: each draw one object, in draw order, with
// auto-model viewports for a side-by-side stereo frame of the given size
// (the left eye's viewport is the left half), and the scene's ordering
// constraints (Object::after) as dependencies.
OOApplication make_application(const Scene& scene, int frame_width, int frame_height, int frame = 0);

}  // namespace oovr
