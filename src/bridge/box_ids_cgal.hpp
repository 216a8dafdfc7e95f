/*
 * box_ids_cgal.hpp: CGAL's 3D boxes whose id is their address (the policy
 * ID_FROM_BOX_ADDRESS, which corefinement and the self-intersection tests use) given
 * an id in the order they are made instead, as CGAL's own ID_EXPLICIT does.
 *
 * box_intersection_d orders boxes with the same lower corner by id. Corefinement
 * makes its faces' boxes and its edges' boxes in two vectors, and which of the two the
 * heap put first decided which intersection it found first, then how it triangulated
 * a flat face through cocircular points: the same volume, other triangles, as soon as
 * the heap's history changed (one more OpenMP thread earlier in the run changed 33
 * triangles of a generated flange's patch). An id taken from a counter as a box is
 * made follows the order of the meshes' faces and edges alone. A copy keeps its id
 * (an address would not: CGAL copies boxes only through pointers for that reason).
 *
 * Every bridge file that uses a CGAL box intersection must see this specialization
 * before CGAL's headers instantiate the class (one definition across the program):
 * boolean_cgal.hpp and mend_cgal.hpp include it first.
 */
#ifndef SR_BOX_IDS_CGAL_HPP
#define SR_BOX_IDS_CGAL_HPP

#include <CGAL/Box_intersection_d/Box_d.h>

#include <cstddef>

namespace CGAL
{
namespace Box_intersection_d
{

template <> class Box_d<double, 3, ID_FROM_BOX_ADDRESS> : public Box_d<double, 3, ID_NONE>
{
  public:
    typedef Box_d<double, 3, ID_NONE> Base;
    typedef double NT;
    typedef std::size_t ID;

    Box_d() : m_id(next()) {}
    Box_d(bool complete) : Base(complete), m_id(next()) {}
    Box_d(NT l[3], NT h[3]) : Base(l, h), m_id(next()) {}
    Box_d(const Bbox_3 &b) : Base(b), m_id(next()) {}
    ID id() const { return m_id; }

  private:
    /* per thread, so boxes made on two threads at once keep their orders */
    static ID next()
    {
        static thread_local ID made = 0;
        return ++made;
    }
    ID m_id;
};

} // namespace Box_intersection_d
} // namespace CGAL

#endif
