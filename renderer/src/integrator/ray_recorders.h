// The three ways WhittedIntegrator::trace records the rays it traces: the hot
// path that only counts them, the auxiliary outputs' per-pixel facts, and the
// debugger's full tree of segments. trace() is a template over them, so the
// hot path pays nothing for what the other two record.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>

#include "geometry/accel.h"
#include "geometry/surface.h"
#include "geometry/surface_material.h"
#include "image/aov.h"
#include "integrator/whitted.h"
#include "rt/debug.pb.h"

namespace rt {
namespace recorders {

inline void count(RayCounts& counts, RayKind kind) {
    (kind == PRIMARY ? counts.camera : kind == REFRACTION ? counts.refraction : counts.reflection) += 1;
}

// Shadow rays from one point towards one light as packets of up to
// Accelerator::kPacketSize, which share their origin (shadows_of).
inline void packet_shadows(RayCounts& counts, const Accelerator& accel, std::span<const Ray> rays, float* visibility,
                           int* ids) {
    counts.shadow += rays.size();
    for (size_t first = 0; first < rays.size(); first += Accelerator::kPacketSize) {
        const size_t n = std::min<size_t>(Accelerator::kPacketSize, rays.size() - first);
        accel.visibility(rays.subspan(first, n), std::span(visibility + first, n));
    }
    std::fill_n(ids, rays.size(), -1);
}

// The hot path: counts rays, records nothing.
struct CountingRecorder {
    RayCounts& counts;
    // The camera ray's hit when a packet found it already: the first ray
    // traced takes it instead of a traversal.
    const Hit* primary = nullptr;

    int closest(const Accelerator& accel, const Ray& ray, RayKind kind, uint32_t, int, vec3, Hit& hit) {
        count(counts, kind);
        if (primary) {
            hit = *primary;
            primary = nullptr;
        } else {
            accel.intersect(ray, hit);
        }
        return -1;
    }
    int shadow(const Accelerator& accel, const Ray& ray, uint32_t, int, uint32_t, float& visibility) {
        ++counts.shadow;
        visibility = accel.visibility(ray);
        return -1;
    }
    void shadows(const Accelerator& accel, std::span<const Ray> rays, uint32_t, int, uint32_t, float* visibility,
                 int* ids) {
        packet_shadows(counts, accel, rays, visibility, ids);
    }
    void surface(int, const SurfaceHit&, const Hit&, const Material&, const SurfaceMaterial&) {}
    void light(int, const Ray&, float, const Light&, vec3) {}
    void contribution(int, vec3) {}
};

// The shadow rays one at a time, for the recorders that record each.
template <class Recorder>
void shadows_one_by_one(Recorder& recorder, const Accelerator& accel, std::span<const Ray> rays, uint32_t depth,
                        int parent, uint32_t light, float* visibility, int* ids) {
    for (size_t i = 0; i < rays.size(); ++i)
        ids[i] = recorder.shadow(accel, rays[i], depth, parent, light, visibility[i]);
}

// The hot path's counts plus the auxiliary outputs (aov.h): the primary hit's
// depth; the albedo and normal of the surface that shows in the pixel, the
// camera ray's hit or, when that is mostly mirror or glass, the first surface
// past it that is not (as Open Image Denoise asks of its guides: a mirror's
// own colour says nothing of what it shows); and, with `costs`, every ray's
// BVH traversal cost. Without costs the rays take the hot path's queries,
// shadow packets and a camera ray's packet hit (`primary`) included.
struct AuxRecorder {
    RayCounts& counts;
    AuxSample& aux;
    bool costs = true;
    const Hit* primary = nullptr;
    int segments = 0;          // closest-hit rays traced so far: the next one's id
    int guide = 0;             // the segment whose surface gives albedo and normal
    RayKind passes = PRIMARY;  // the kind of ray that passes the guide on (PRIMARY: none)
    vec3 tint{1.0f};           // the path weight of the guide's ray: the mirrors' and glass's colour

    int closest(const Accelerator& accel, const Ray& ray, RayKind kind, uint32_t, int parent, vec3 weight,
                Hit& hit) {
        count(counts, kind);
        if (primary) {
            hit = *primary;
            primary = nullptr;
        } else if (costs) {
            accel.intersect(ray, hit, aux.cost);
        } else {
            accel.intersect(ray, hit);
        }
        const int id = segments++;
        // Camera rays have unit directions: t is the distance.
        if (kind == PRIMARY && hit.found()) {
            aux.depth = hit.t;
            aux.alpha = 1.0f;
        }
        // Glass passes the guide on through its refraction, or its reflection
        // when the light cannot get through (total internal reflection).
        if (parent == guide && passes != PRIMARY && (kind == passes || passes == REFRACTION)) {
            guide = id;
            passes = PRIMARY;
            tint = weight;
        }
        return id;
    }
    int shadow(const Accelerator& accel, const Ray& ray, uint32_t, int, uint32_t, float& visibility) {
        ++counts.shadow;
        visibility = costs ? accel.visibility(ray, aux.cost) : accel.visibility(ray);
        return -1;
    }
    void shadows(const Accelerator& accel, std::span<const Ray> rays, uint32_t depth, int parent, uint32_t light,
                 float* visibility, int* ids) {
        if (costs)
            shadows_one_by_one(*this, accel, rays, depth, parent, light, visibility, ids);
        else
            packet_shadows(counts, accel, rays, visibility, ids);
    }
    void surface(int segment, const SurfaceHit& s, const Hit&, const Material& m, const SurfaceMaterial& sm) {
        if (segment != guide) return;
        aux.normal = s.ns;
        // The shares of the light the surface sends back as the integrator
        // splits them: Phong (diffuse), mirror, and what the glass lets
        // through. A BLEND surface's coverage scales them all alike: it keeps
        // its own colour, as the first surface three.js draws does.
        const vec3 opaque = vec3(1.0f) - m.transmission;
        const vec3 mirror = opaque * sm.reflectance;
        const vec3 through = m.transmission;
        const float delta = max_component(mirror + through);
        if (delta <= max_component(opaque * sm.diffuse)) {
            aux.albedo = tint * sm.diffuse;
            return;
        }
        // Until a ray shows what lies past it, the mirror's or glass's own colour.
        aux.albedo = glm::min(tint * (mirror + through), vec3(1.0f));
        passes = max_component(through) >= max_component(mirror) ? REFRACTION : REFLECTION;
    }
    // A light has no albedo; its normal faces the camera, which is outside it.
    void light(int segment, const Ray& ray, float t, const Light& light, vec3) {
        if (segment == 0) {
            aux.depth = t;
            aux.alpha = 1.0f;
        }
        if (segment == guide) aux.normal = glm::normalize(ray.at(t) - light.position);
    }
    void contribution(int, vec3) {}
};

inline void set_vec3(google::protobuf::RepeatedField<float>* field, vec3 v) {
    field->Clear();
    field->Add(v.x);
    field->Add(v.y);
    field->Add(v.z);
}

// The debugger's view: every ray as a segment, with the BVH nodes it visited.
struct DebugRecorder {
    DebugPath& path;
    float miss_length;

    RaySegment& add(const Ray& ray, RayKind kind, uint32_t depth, int parent, const TraversalRecord& record) {
        RaySegment& segment = *path.add_segments();
        set_vec3(segment.mutable_origin(), ray.origin);
        segment.set_kind(kind);
        segment.set_depth(depth);
        segment.set_parent(parent);
        segment.mutable_visited_nodes()->Add(record.visited_nodes.begin(), record.visited_nodes.end());
        segment.mutable_visited_leaves()->Add(record.visited_leaves.begin(), record.visited_leaves.end());
        segment.set_triangles_tested(record.triangles_tested);
        for (const EnteredTree& visit : record.entered) {
            rt::TreeVisit& tree = *segment.add_trees();
            const bool world = visit.entry == AccelScene::kWorldEntry;
            tree.set_tree(world ? BVH_TREE_WORLD : BVH_TREE_INSTANCE);
            if (!world) tree.set_instance(visit.entry);
            tree.mutable_visited_nodes()->Add(visit.visited_nodes.begin(), visit.visited_nodes.end());
            tree.mutable_visited_leaves()->Add(visit.visited_leaves.begin(), visit.visited_leaves.end());
        }
        return segment;
    }

    int closest(const Accelerator& accel, const Ray& ray, RayKind kind, uint32_t depth, int parent,
                vec3 weight, Hit& hit) {
        TraversalRecord record;
        const bool found = accel.intersect(ray, hit, record);
        RaySegment& segment = add(ray, kind, depth, parent, record);
        segment.set_outcome(found ? HIT : MISS);
        const float t = found ? hit.t : miss_length;
        segment.set_t(t);
        set_vec3(segment.mutable_end(), ray.at(t));
        set_vec3(segment.mutable_weight(), weight);
        return path.segments_size() - 1;
    }
    int shadow(const Accelerator& accel, const Ray& ray, uint32_t depth, int parent, uint32_t light,
               float& visibility) {
        TraversalRecord record;
        visibility = accel.visibility(ray, record);
        RaySegment& segment = add(ray, SHADOW, depth, parent, record);
        segment.set_outcome(visibility == 0.0f ? OCCLUDED : REACHED_LIGHT);
        segment.set_light(light);
        // A shadow ray towards a directional light has no end: drawn as a miss.
        const float t = std::isinf(ray.t_max) ? miss_length : ray.t_max;
        segment.set_t(t);
        set_vec3(segment.mutable_end(), ray.at(t));
        return path.segments_size() - 1;
    }
    void shadows(const Accelerator& accel, std::span<const Ray> rays, uint32_t depth, int parent, uint32_t light,
                 float* visibility, int* ids) {
        shadows_one_by_one(*this, accel, rays, depth, parent, light, visibility, ids);
    }
    void surface(int index, const SurfaceHit& s, const Hit& hit, const Material& m, const SurfaceMaterial&) {
        RaySegment& segment = *path.mutable_segments(index);
        set_vec3(segment.mutable_end(), s.p);
        set_vec3(segment.mutable_normal(), s.ns);
        segment.set_material(int32_t(s.material));
        segment.set_material_name(m.name);
        segment.set_primitive(hit.primitive);
    }
    // No material: the segment names the light it ended on.
    void light(int index, const Ray& ray, float t, const Light& light, vec3 radiance) {
        RaySegment& segment = *path.mutable_segments(index);
        segment.set_outcome(REACHED_LIGHT);
        segment.set_t(t);
        const vec3 end = ray.at(t);
        set_vec3(segment.mutable_end(), end);
        set_vec3(segment.mutable_normal(), glm::normalize(end - light.position));
        segment.set_material(-1);
        segment.set_material_name(light.name);
        set_vec3(segment.mutable_contribution(), radiance);
    }
    void contribution(int index, vec3 c) { set_vec3(path.mutable_segments(index)->mutable_contribution(), c); }
};

}  // namespace recorders
}  // namespace rt
