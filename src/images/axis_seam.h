/*
 * axis_seam.h: the seam where a turn's images meet on the axis. Every turn maps the
 * axis onto itself, so no image of the scan carries material at the axis where a chip
 * crosses it: each image lacks a wedge whose edge is the axis, the images' union covers
 * everything round the axis but the line itself, and the exact union keeps that line as
 * a zero-width slit of sliver triangles (on a solid shaft whose end chip crosses the
 * axis, a slit 12 mm deep: the restored part deviates by the shaft's radius there).
 *
 * The seam is closed by a thin pin along the axis wherever the clipped image Q and the
 * scan together hold material all round the axis: at the 8 voxel centres of a small
 * ring about it, a quarter of the image method's pitch out. The pin overlaps the scan,
 * so the union meets no edge of it on the axis; the patch (Q less the scan) keeps only
 * the pin's part in the loss. A real bore is wider than that ring and gets no pin.
 */
#ifndef SR_AXIS_SEAM_H
#define SR_AXIS_SEAM_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "base/status.h"

/* Unites q (closed, aligned frame, axis = z) with a pin of radius ring_mm / 2 along
 * every run of z (steps of ring_mm) where q or the aligned scan holds material at all
 * 8 points of the ring of voxel centres ring_mm about the axis, q one of them at least
 * and the scan not all (so the loss reaches the axis). q is replaced only on success,
 * when a pin was added; *pins (may be NULL) receives the number of runs pinned. */
sr_status sr_axis_seam_close(sr_mesh *q, const sr_mesh *scan, double ring_mm, size_t *pins,
                             sr_err *err);

#endif
