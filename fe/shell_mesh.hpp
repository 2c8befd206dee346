#pragma once
// A generated thick spherical shell: the structure of the IB verification cases and examples.
#include "fe/mesh.hpp"

namespace ibvalve::fe {

/// A thick spherical shell r in [r_inner, r_outer] about `center` made of trilinear hexahedra: each
/// face of a cube is split into n x n patches mapped to the sphere by the equiangular gnomonic map
/// (Ronchi, Iacono & Paolucci 1996, "the cubed sphere"), with `layers` cells through the thickness.
/// Nodes on the patches' shared edges are merged. Groups: volume "body", surfaces "inner", "outer".
fe::Mesh spherical_shell_mesh(const fe::Vec3& center, double r_inner, double r_outer, int n, int layers);

} // namespace ibvalve::fe
