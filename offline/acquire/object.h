// The objects of the virtual acquisition setup: a mesh and its texture atlas (Lensch et al.
// 2003, section 7.1: every quantity lives on the atlas), and what a point in space sees
// of it (visibility and shadowing by depth maps, section 7.2).
//
// Usage:
//   sepal::AcqObject obj; std::string err;
//   if (!sepal::make_object("torus", 128, &obj, &err)) ...
//   sepal::PointView cam;  sepal::view_from_point(obj, glm::dvec3(0, -4, 1), 512, &cam);
//   for (int i : obj.atlas.texels) if (cam.ok[i]) { cam.local[i] ... }   // direction in the texel's frame
//
// The atlas is the mesh's own UV square at res x res texels: the built-in meshes (sphere,
// torus, wave; sepal_rt.h) map [0,1]^2 one to one onto their surface, so a texel is a surface
// point with a position and a shading frame (normal, tangent, bitangent), rasterized from the
// triangles in UV space (texel centres; the first triangle covering a centre wins). Texels
// no triangle covers are invalid (none on the built-in meshes).
// Visibility from a point p: the texel faces p (the direction is above its shading horizon),
// lies inside the frustum that frames the object from p, and is not hidden: its distance to p
// is at most the nearest surface's distance along the same ray (a depth map rendered by the
// software rasterizer, sepal_raster.h) plus a bias. The same test is the camera's visibility
// and the light's shadowing.
// Limits: atlas res 8..1024; meshes with UVs in [0,1]^2 (an OBJ whose UVs overlap gives
// texels that stand for several surface points: not supported); depth maps 64..4096.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sepal/sepal_rt.h"

namespace sepal {

struct SurfaceAtlas {
    int res = 0;
    // Per texel (res * res, row v = 0 first); frames are unit and orthonormal.
    std::vector<glm::vec3> position, normal, tangent, bitangent;
    std::vector<uint8_t> valid;
    std::vector<int> texels;  // indices of the valid texels, in order
    // Whether the surface continues across the u = 0 / 1 and the v = 0 / 1 edges of the UV
    // square (the torus both ways, the sphere around only: its v runs pole to pole).
    bool wrap_u = false, wrap_v = false;
    glm::vec3 local(int texel, const glm::dvec3& world_dir) const;  // world -> (t, b, n)
    // The texel dx, dy texels from `texel` on the surface: across a wrapping edge, or -1 past
    // one that does not wrap.
    int step(int texel, int dx, int dy) const;
};

struct AcqObject {
    std::string name;
    std::vector<sepal_vertex> vertices;
    std::vector<uint16_t> indices;
    SurfaceAtlas atlas;
    double radius = 1;  // bounding sphere around the origin
    bool closed = true;  // no boundary: back faces are always hidden by front faces
    sepal_mesh mesh() const;  // a view into vertices / indices
};

// "sphere" (radius 1), "torus" (radii 0.7 and 0.3: it shadows and hides itself), "wave"
// (the height field of sepal_mesh_wave: an open surface with bumps).
bool make_object(const std::string& name, int atlas_res, AcqObject* out, std::string* err);
// Rasterizes the mesh's triangles into a res x res atlas over its UV square.
bool build_atlas(const sepal_mesh& mesh, int res, SurfaceAtlas* out, std::string* err);

// What a point (a camera or a point light) sees of an object, per texel.
struct PointView {
    glm::dvec3 point{0.0};
    std::vector<uint8_t> ok;        // faces the point, inside the frustum, not hidden
    std::vector<glm::vec3> local;   // unit direction to the point in the texel's frame
    std::vector<float> dist2;       // squared distance to the point
};

// Depth-map resolution for view_from_point when the caller gives 0.
constexpr int kDefaultDepthRes = 512;
void view_from_point(const AcqObject& obj, const glm::dvec3& point, int depth_res, PointView* out);

}  // namespace sepal
