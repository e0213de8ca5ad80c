// model.glb draws a mesh that several nodes share once per node (the
// renderer's instances, geometry/instance.h): each such set of meshes becomes
// one InstancedMesh, so the GPU gets the vertices once and one draw call.
// Mirroring placements stay meshes of their own: three.js turns the winding
// around for an object whose matrix mirrors, not for one instance of many.
import * as THREE from "three";

/** Replaces meshes under `root` that share geometry and material with InstancedMeshes; returns how many were made. */
export function instanceSharedMeshes(root) {
  root.updateMatrixWorld(true);
  const groups = new Map();
  root.traverse((object) => {
    if (!object.isMesh || object.isInstancedMesh || object.isSkinnedMesh || Array.isArray(object.material)) return;
    if (object.matrixWorld.determinant() < 0) return;
    const key = `${object.geometry.uuid}/${object.material.uuid}`;
    if (!groups.has(key)) groups.set(key, []);
    groups.get(key).push(object);
  });
  const inverseRoot = root.matrixWorld.clone().invert();
  let made = 0;
  for (const meshes of groups.values()) {
    if (meshes.length < 2) continue;
    const [first] = meshes;
    const instanced = new THREE.InstancedMesh(first.geometry, first.material, meshes.length);
    instanced.name = `${first.name || "mesh"} (${meshes.length} instances)`;
    const matrix = new THREE.Matrix4();
    meshes.forEach((mesh, i) => {
      instanced.setMatrixAt(i, matrix.multiplyMatrices(inverseRoot, mesh.matrixWorld));
      mesh.parent.remove(mesh);
    });
    instanced.instanceMatrix.needsUpdate = true;
    instanced.computeBoundingSphere();
    root.add(instanced);
    made++;
  }
  return made;
}
