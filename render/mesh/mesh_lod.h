/* mesh_lod.h: levels of detail by retinal eccentricity (issue 13, 5a): each
 * object of a scene takes the coarsest level of its mesh's collapse record
 * that the acuity model still allows where it is on the screen.
 *
 * For an object whose bounding sphere projects to a circle of radius r
 * pixels, the eye resolves rho(e) samples per pixel there (gaze2d.h), e the
 * eccentricity of the circle's point nearest the gaze (its centre's
 * distance less r, so an object the gaze falls on is at e = 0).  The object
 * gets at most
 *     faces = 2 pi r^2 rho(e) / MESH_LOD_SAMPLES_PER_FACE
 * faces (2 pi r^2: the front and back halves of its silhouette's area), i.e.
 * one face per resolved sample: a face smaller than the sample spacing
 * there changes no sample.  The level is mesh_record_level_for_faces of that
 * budget (level 0, full detail, when the budget is at least the mesh's
 * faces).  An object wholly off the image takes the coarsest level; one the
 * eye is inside (or whose centre is behind the eye) keeps full detail.
 * The budget rule is ours: the paper (seed 004 §7) names levels of detail
 * by eccentricity as future work and gives no rule. */
#ifndef PP5_MESH_LOD_H
#define PP5_MESH_LOD_H

#include "render/gaze2d.h"
#include "mesh_raster.h"
#include "mesh_scene.h"

#define MESH_LOD_SAMPLES_PER_FACE 1.0

/* levels[o] for every object (s's records must be built); *faces = the
 * scene's faces at those levels. */
void mesh_lod_choose(const mesh_scene_t *s, const raster_camera_t *cam, const gaze_model_t *g,
                     double gaze_x, double gaze_y, int *levels, long *faces);

#endif
