/*
 * classify_cgal.hpp: what the local booleans share beyond boolean_cgal.hpp (the local
 * union, union_local_cgal.cpp with union_result_cgal.cpp, and the local intersection,
 * clip_local_cgal.cpp): the corefinement visitor that takes CGAL's own classification
 * of the patches, the neighbourhood N of b cut out of a as arrays and as a halfedge
 * mesh (both defined in union_local_cgal.cpp), and the placing of the patches no
 * intersection edge bounds. Private to src/bridge/; included after boolean_cgal.hpp.
 */
#ifndef SR_CLASSIFY_CGAL_HPP
#define SR_CLASSIFY_CGAL_HPP

#include "bridge/boolean_cgal.hpp"

#include <CGAL/Polygon_mesh_processing/corefinement.h>

#include <cstdint>
#include <vector>

#include <cmath>

namespace sr_bool
{

/* A corefinement visitor that asks CGAL's output builder for its classification of the
 * patches (the parts of each surface between intersection edges) instead of a boolean's
 * output: the builder does this when no output is requested and the visitor declares
 * Has_extra_functions (CGAL 5.5, Face_graph_output_builder.h). It is the builder's own
 * exact, orientation-around-the-edge classification, also valid where an operand is
 * open (its boolean output path is not: CGAL 5.5's consistency check for open operands
 * rejects every patch it finds inside). */
struct Classify_visitor : public PMP::Corefinement::Default_visitor<Mesh> {
    typedef int Has_extra_functions;
    Patch_flags *flags; /* [0] first operand, [1] second */
    const Mesh *first;
    std::vector<uint32_t> *node_vertex; /* [0], [1]: per intersection node, the
                                         * operand's vertex at it (no_vertex if none) */

    void record(std::size_t node, Vertex_index v, const Mesh &tm)
    {
        std::vector<uint32_t> &m = node_vertex[&tm == first ? 0 : 1];
        if (m.size() <= node)
            m.resize(node + 1, no_vertex);
        m[node] = static_cast<uint32_t>(v.idx());
    }

    /* a vertex made for a node (an edge or a face of this operand was cut there) */
    void new_vertex_added(std::size_t node, Vertex_index v, const Mesh &tm) { record(node, v, tm); }

    /* an operand's own vertex at a node: an end of the cutting edge h1, or the vertex
     * of the other operand the edge passes through */
    void intersection_point_detected(std::size_t node, int sdim, Mesh::Halfedge_index h1,
                                     Mesh::Halfedge_index h2, const Mesh &tm1, const Mesh &tm2,
                                     bool is_target_coplanar, bool is_source_coplanar)
    {
        if (is_target_coplanar)
            record(node, tm1.target(h1), tm1);
        if (is_source_coplanar)
            record(node, tm1.source(h1), tm1);
        if (sdim == PMP::Corefinement::ON_VERTEX)
            record(node, tm2.target(h2), tm2);
    }

    template <class Fim>
    void export_flags(Fim fim, const std::vector<std::size_t> &ids,
                      const boost::dynamic_bitset<> &inside,
                      const boost::dynamic_bitset<> &coplanar,
                      const boost::dynamic_bitset<> &coplanar_union,
                      const boost::dynamic_bitset<> &not_set, Mesh &tm)
    {
        Patch_flags &f = flags[&tm == first ? 0 : 1];
        f.patch.assign(tm.num_faces(), 0);
        for (Mesh::Face_index fd : tm.faces())
            f.patch[fd.idx()] = ids[get(fim, fd)];
        f.inside = inside;
        f.coplanar = coplanar;
        f.coplanar_union = coplanar_union;
        f.not_set = not_set;
        f.have = true;
    }

    template <class H>
    void register_halfedge_pair(H, H, bool, bool, bool, bool, bool = false, bool = false,
                                bool = false, bool = false)
    {
    }
};

/* N's triangles (in[t] set, n of them) as compact arrays in the frame xf maps a into
 * (NULL: a's own): xyz, tri, and orig (a's vertex number of each vertex). turned: each
 * triangle's last two corners swapped (sr_mesh_flip: a reflection's image faces out). */
void neighbourhood_arrays(const sr_mesh *a, const double *xf, const std::vector<uint8_t> &in,
                          size_t n, std::vector<double> &xyz, std::vector<uint32_t> &tri,
                          std::vector<uint32_t> &orig, bool turned = false);

/* The neighbourhood as a halfedge mesh with property "v:orig" (a's vertex number), from
 * its arrays: only vertices some triangle uses. False when a triangle is refused. */
bool build_neighbourhood(const sr_mesh &loc, const std::vector<uint32_t> &loc_orig, Mesh &sm);

/* Hands each patch of tm with no intersection edge (f.not_set), once, to decide(pid,
 * point) with a point of it (its first face's centroid); decide marks the patch and
 * returns false to give up, which this returns. */
template <class Decide>
inline bool classify_free_patches(const Mesh &tm, const Patch_flags &f, Decide decide)
{
    boost::dynamic_bitset<> done(f.not_set.size());
    for (Mesh::Face_index fd : tm.faces()) {
        std::size_t pid = f.patch[fd.idx()];
        if (!f.not_set.test(pid) || done.test(pid))
            continue;
        done.set(pid);
        Mesh::Halfedge_index h = tm.halfedge(fd);
        if (!decide(pid, CGAL::centroid(tm.point(tm.source(h)), tm.point(tm.target(h)),
                                        tm.point(tm.target(tm.next(h))))))
            return false;
    }
    return true;
}

/* The box (min xyz, max xyz) of box_b grown by margin on every side, or by 1 % of its
 * diagonal when margin is not positive: the neighbourhood a local boolean takes of the
 * large operand. Returns the growth used. */
inline double grown_box(const double box_b[6], double margin, double box[6])
{
    double diag = std::sqrt((box_b[3] - box_b[0]) * (box_b[3] - box_b[0]) +
                            (box_b[4] - box_b[1]) * (box_b[4] - box_b[1]) +
                            (box_b[5] - box_b[2]) * (box_b[5] - box_b[2]));
    double grow = margin > 0 ? margin : 0.01 * diag;
    for (int k = 0; k < 3; k++) {
        box[k] = box_b[k] - grow;
        box[3 + k] = box_b[3 + k] + grow;
    }
    return grow;
}

} // namespace sr_bool

#endif
