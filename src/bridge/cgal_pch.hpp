/*
 * cgal_pch.hpp: the CGAL headers most of the CGAL bridge files (*_cgal.cpp) share,
 * compiled once per build into a precompiled header that every one of them is compiled
 * with (the Makefile's CGAL_PCH, passed by -include). Parsing these headers took about
 * 8 s of each file's 8-60 s: 16 files, 7 min of CPU in all, 5 min with the header.
 * Each file still includes what it uses; nothing here is ours but the order. As
 * boolean_cgal.hpp and mend_cgal.hpp require, the rounding macro and the boxes' id
 * specialisation come before any CGAL header.
 */
#ifndef SR_CGAL_PCH_HPP
#define SR_CGAL_PCH_HPP

#define CGAL_ALWAYS_ROUND_TO_NEAREST 1 /* see boolean_cgal.hpp */
#include "bridge/box_ids_cgal.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <vector>

#endif
