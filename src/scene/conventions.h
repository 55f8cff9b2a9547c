// The rules that differ between the two courses whose scene files raycast reads, gathered in
// one value that the camera and the shading receive (a "profile"), instead of conditions spread
// through the code. Conventions::course() is the default; Conventions::mit6837() reproduces the
// MIT 6.837 (Fall 2004) sample images.
#pragma once

#include "math/vec.h"

namespace raycast {

/// Which image axis `angle` (or an orthographic `size`) spans when width != height.
enum class FovAxis {
    Vertical,  ///< angle is the vertical field of view; pixels are square (MIT 6.837)
    /// Both axes span angle, so pixels are stretched: the course handout's f_x = (w/2)/tan(angle/2)
    /// and f_y = (h/2)/tan(angle/2), which most course solutions implement (the course's default).
    Both,
};

enum class SpecularModel {
    Phong,                ///< ks·max(0, V·R)^s, never gated by N·L (the course's handout)
    BlinnClampedByNdotL,  ///< ks·max(0, N·H)^s where N·L > 0, else 0 (MIT assignment 3)
    BlinnTimesNdotL,      ///< ks·max(0, N·H)^s·max(0, N·L) (MIT's "specular fix")
};

struct Conventions {
    float pixel_offset = 0;   ///< added to integer pixel coordinates: 0 (course) or 0.5 (centres)
    FovAxis fov_axis = FovAxis::Both;
    SpecularModel specular = SpecularModel::Phong;
    float default_shininess = 0;          ///< when a material gives none: 0 (course), 1 (MIT)
    bool ambient_without_lights = false;  ///< a scene without a Lights block gets ambient 1 1 1
    bool orthographic_sees_behind = false;  ///< orthographic rays start at t = −∞
    bool black_back_faces = false;        ///< hits on back faces are black (MIT without -shade_back)
    bool shade_back_faces = false;        ///< flip the normal of back-face hits towards the viewer

    static Conventions course() { return Conventions{}; }
    static Conventions mit6837() {
        Conventions c;
        c.pixel_offset = 0.5f;
        c.fov_axis = FovAxis::Vertical;
        c.specular = SpecularModel::BlinnClampedByNdotL;
        c.default_shininess = 1;
        c.ambient_without_lights = true;
        c.orthographic_sees_behind = true;
        c.black_back_faces = true;
        return c;
    }
};

}  // namespace raycast
