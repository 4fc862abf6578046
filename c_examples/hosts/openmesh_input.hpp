// openmesh_input.hpp: an OpenMesh polygon mesh as ccss input (shared by
// openmesh_limit.cpp and openmesh_tessellate.cpp): its points as x y z per
// vertex and its faces as sizes + vertex indices, in OpenMesh's numbering
// and orientation, the arrays ccss_host::Limit takes.
//
// A template over the mesh type, so that this header needs no OpenMesh
// include of its own. Header-only.
#ifndef CCSS_OPENMESH_INPUT_HPP
#define CCSS_OPENMESH_INPUT_HPP

#include <cstdint>
#include <vector>

namespace ccss_host {

/// Points and faces of a polygon mesh, as the ccss C API takes them.
struct MeshArrays {
    std::vector<double> positions;  // x y z per vertex
    std::vector<uint32_t> sizes;    // vertices per face
    std::vector<uint32_t> indices;  // the faces' vertex indices, concatenated
};

/// The arrays of an OpenMesh mesh (vertices and faces in OpenMesh's order).
template <class Mesh>
MeshArrays openmesh_arrays(const Mesh& mesh)
{
    MeshArrays a;
    a.positions.reserve(3 * mesh.n_vertices());
    a.sizes.reserve(mesh.n_faces());
    for (auto vh : mesh.vertices())
        for (int k = 0; k < 3; ++k) a.positions.push_back(mesh.point(vh)[k]);
    for (auto fh : mesh.faces()) {
        uint32_t n = 0;
        for (auto vh : mesh.fv_range(fh)) {
            a.indices.push_back(static_cast<uint32_t>(vh.idx()));
            ++n;
        }
        a.sizes.push_back(n);
    }
    return a;
}

}  // namespace ccss_host

#endif
