#pragma once
/// Pinhole camera. Pixel (x, y) with y = 0 at the top; sub-pixel offsets in [0, 1).
#include "accel/core/geometry.h"

namespace arbor::engine {

using accel::Vec3f;

struct Camera {
    Vec3f eye{0, 0, 5};
    Vec3f look_at{0, 0, 0};
    Vec3f up{0, 1, 0};
    float vfov_degrees = 40.0f;

    /// Fixes the basis for an image of width x height; call before ray().
    void prepare(int width, int height);
    /// Primary ray through image point (px, py) in pixels (e.g. x + 0.5 for the pixel centre).
    accel::Ray ray(float px, float py) const;
    /// A camera that frames `b` from the front-right-above, whole box in view. "Above" is along
    /// `up` (default +y): the view direction used for +y up is turned by the smallest rotation
    /// taking +y to `up`, so a Z-up scan framed with up = (0, 0, 1) is seen from -y, upright.
    static Camera framing(const accel::Bounds& b, float vfov_degrees = 40.0f, Vec3f up = {0, 1, 0});

private:
    Vec3f origin_, corner_, du_, dv_;  // corner_ = direction to pixel (0,0); du_/dv_ per pixel
};

}  // namespace arbor::engine
