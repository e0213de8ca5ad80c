// What the BVH boxes are: the tree's kind from BvhBoxes.node_width, a swatch
// for each kind of box, and the count of the boxes shown, beside the level
// slider.
import { BOX_COLORS } from "./bvh-boxes.js";

/** One sentence on the tree the renderer traverses, a node holding up to `nodeWidth` children. */
export function describeTree(nodeWidth) {
  if (!nodeWidth) return "";
  const kind = nodeWidth === 2 ? "Binary BVH" : `${nodeWidth}-wide BVH`;
  return `${kind}: a ray tests a node's up to ${nodeWidth} child boxes together, then the triangles of the leaves it enters.`;
}

function swatch(color, label) {
  const span = document.createElement("span");
  span.className = "box-kind";
  const mark = document.createElement("span");
  mark.className = "swatch";
  mark.style.background = color;
  span.append(mark, label);
  return span;
}

/** Fills `element` for a tree of `nodeWidth` (0: nothing known yet, the element hidden). */
export function renderBvhLegend(element, nodeWidth) {
  element.hidden = !nodeWidth;
  element.dataset.nodeWidth = String(nodeWidth || 0);
  if (!nodeWidth) {
    element.replaceChildren();
    return;
  }
  element.replaceChildren(describeTree(nodeWidth), " ",
    swatch(BOX_COLORS.node, "node box"), " ", swatch(BOX_COLORS.leaf, "leaf box"));
}

const plural = (n, one, many) => `${n.toLocaleString()} ${n === 1 ? one : many}`;
const of = (part, all) => (part === all ? all.toLocaleString() : `${part.toLocaleString()} of ${all.toLocaleString()}`);

/** "3 of 6 boxes, 3 of 6 leaves (14 triangles) · level 1/1" from a BvhBoxes change event's detail. */
export function boxCountText({ level, totalLevels, shown, total, shownLeaves, totalLeaves, leafTriangles }) {
  if (!total) return "–";
  const triangles = shownLeaves ? ` (${plural(leafTriangles, "triangle", "triangles")})` : "";
  const leaves = `${of(shownLeaves, totalLeaves)} ${totalLeaves === 1 ? "leaf" : "leaves"}${triangles}`;
  return `${of(shown, total)} boxes, ${leaves} · level ${level}/${totalLevels - 1}`;
}
