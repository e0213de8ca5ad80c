#include "ours_sah.h"

namespace rt::bench {

// Half areas, as Embree sums them; the ratio is what counts.
double embree_formula_sah(const bvh::WideBvh& bvh) {
    if (bvh.empty()) return 0.0;
    const double root_area = 0.5 * bvh.nodes[0].bounds().surface_area();
    if (root_area <= 0.0) return 0.0;
    double node_sah = root_area;  // the root, entered with the scene's box
    double leaf_sah = 0.0;
    for (const bvh::WideNode& node : bvh.nodes)
        for (uint32_t c = 0; c < bvh::kWideWidth; ++c) {
            const bvh::ChildRef child = node.child[c];
            if (child.empty()) continue;
            const double area = 0.5 * double(node.child_bounds(c).surface_area());
            if (child.is_leaf()) leaf_sah += area * child.block_count();
            else node_sah += area;
        }
    return (node_sah + leaf_sah) / root_area;
}

}  // namespace rt::bench
