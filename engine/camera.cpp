#include "engine/camera.h"

#include <glm/glm.hpp>

#include <cmath>

namespace arbor::engine {

namespace {
glm::vec3 g(const Vec3f& v) { return {v.x, v.y, v.z}; }
Vec3f a(const glm::vec3& v) { return {v.x, v.y, v.z}; }
}  // namespace

void Camera::prepare(int width, int height) {
    const glm::vec3 forward = glm::normalize(g(look_at) - g(eye));
    const glm::vec3 right = glm::normalize(glm::cross(forward, g(up)));
    const glm::vec3 down = glm::cross(forward, right);
    const float half_h = std::tan(glm::radians(vfov_degrees) * 0.5f);
    const float half_w = half_h * float(width) / float(height);
    const glm::vec3 du = right * (2.0f * half_w / float(width));
    const glm::vec3 dv = down * (2.0f * half_h / float(height));
    origin_ = eye;
    corner_ = a(forward - right * half_w - down * half_h);
    du_ = a(du);
    dv_ = a(dv);
}

accel::Ray Camera::ray(float px, float py) const {
    accel::Ray r;
    r.org = origin_;
    r.dir = corner_ + du_ * px + dv_ * py;
    r.tnear = 0.0f;
    return r;
}

Camera Camera::framing(const accel::Bounds& b, float vfov, Vec3f up_vector) {
    Camera c;
    c.vfov_degrees = vfov;
    const Vec3f center = b.center();
    const Vec3f ext = b.extent();
    const float radius = 0.5f * std::sqrt(ext.x * ext.x + ext.y * ext.y + ext.z * ext.z);
    const float dist = radius / std::sin(glm::radians(vfov) * 0.5f) * 1.05f;
    glm::vec3 dir = glm::normalize(glm::vec3(0.55f, 0.35f, 1.0f));
    const glm::vec3 y(0.0f, 1.0f, 0.0f);
    const float up_len = glm::length(g(up_vector));
    const glm::vec3 up = up_len > 0.0f && std::isfinite(up_len) ? g(up_vector) / up_len : y;
    const glm::vec3 axis = glm::cross(y, up);
    const float s = glm::length(axis), cosine = glm::dot(y, up);
    if (s > 1e-6f) {
        // Rodrigues' rotation by the angle between +y and up, about their common perpendicular.
        const glm::vec3 k = axis / s;
        dir = dir * cosine + glm::cross(k, dir) * s + k * glm::dot(k, dir) * (1.0f - cosine);
    } else if (cosine < 0.0f) {
        dir = glm::vec3(dir.x, -dir.y, -dir.z);  // upside down: half a turn about x
    }
    c.look_at = center;
    c.eye = a(g(center) + dir * std::max(dist, 1e-6f));
    c.up = a(up);
    return c;
}

}  // namespace arbor::engine
