// The drawn world: three.js objects built once from a Scene message (MuJoCo geom
// semantics), then moved by the dynamic body poses of State messages or a replay.
//
// Draw calls are what a software renderer and a standalone headset pay for: everything
// that never moves is one mesh per material, and every moving body's geoms (arm links,
// fingers, boxes) are instances of one THREE.BatchedMesh per material (one multi-draw
// each), placed at their body's pose every frame. A body keeps an empty group that carries
// its pose (the head camera hangs from the head's).

import * as THREE from "three";
import { mergeGeometries } from "three/examples/jsm/utils/BufferGeometryUtils.js";
import type {
  BodyDescription,
  GeomDescription,
  MaterialDescription,
  Pose,
  Scene,
  TextureDescription,
} from "../protocol";
import { WORLD_TO_THREE, applyPose } from "./frames";

/** A plane of size 0 is infinite in MuJoCo; draw it this big (half extent, m). */
const INFINITE_PLANE_HALF = 25;
const HEAD_CAMERA_OFFSET = 0.08;

function geometryFor(geom: GeomDescription): THREE.BufferGeometry | null {
  const [a, b, c] = geom.size;
  switch (geom.shape) {
    case "box":
      return new THREE.BoxGeometry(2 * a, 2 * b, 2 * c);
    case "sphere":
      return new THREE.SphereGeometry(a, 20, 14);
    case "ellipsoid":
      return new THREE.SphereGeometry(1, 20, 14).scale(a, b, c);
    case "capsule":
      // MuJoCo: radius, half-length of the cylindrical part, along z; three.js: along y.
      return new THREE.CapsuleGeometry(a, 2 * b, 6, 16).rotateX(Math.PI / 2);
    case "cylinder":
      return new THREE.CylinderGeometry(a, a, 2 * b, 24).rotateX(Math.PI / 2);
    case "plane": {
      const hx = a > 0 ? a : INFINITE_PLANE_HALF;
      const hy = b > 0 ? b : INFINITE_PLANE_HALF;
      return new THREE.PlaneGeometry(2 * hx, 2 * hy);
    }
    default:
      return null;
  }
}

/** MuJoCo's shininess (0-1) as an OpenGL/three.js Phong exponent. */
const SHININESS_SCALE = 128;

/** A model texture's pixels (RGB, base64) as a repeating three.js texture. */
export function textureFor(description: TextureDescription): THREE.DataTexture {
  const rgb = Uint8Array.from(atob(description.rgb), (c) => c.charCodeAt(0));
  const texels = description.width * description.height;
  const rgba = new Uint8Array(4 * texels);
  for (let i = 0; i < texels; i += 1) {
    rgba[4 * i] = rgb[3 * i] ?? 0;
    rgba[4 * i + 1] = rgb[3 * i + 1] ?? 0;
    rgba[4 * i + 2] = rgb[3 * i + 2] ?? 0;
    rgba[4 * i + 3] = 255;
  }
  const texture = new THREE.DataTexture(rgba, description.width, description.height, THREE.RGBAFormat);
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.wrapS = THREE.RepeatWrapping;
  texture.wrapT = THREE.RepeatWrapping;
  texture.repeat.set(description.repeat[0], description.repeat[1]);
  texture.magFilter = THREE.LinearFilter;
  texture.minFilter = THREE.LinearMipmapLinearFilter;
  texture.generateMipmaps = true;
  texture.needsUpdate = true;
  return texture;
}

/** The three.js material for a geom: its colour, shaded as its MuJoCo material says
 * (Phong highlights, glow, texture), or matte (Lambert) when it has none. One material per
 * (model material, colour), so that geoms sharing both share a draw call. */
export function materialFor(
  geom: GeomDescription,
  materials: readonly MaterialDescription[],
  cache: Map<string, THREE.Material>,
): THREE.Material {
  const [r, g, b, alpha] = geom.rgba;
  const key = `${geom.shape === "plane" ? "p" : "m"}:${geom.material}:${geom.rgba.join(",")}`;
  const cached = cache.get(key);
  if (cached !== undefined) return cached;
  const colour = new THREE.Color(r, g, b);
  const common = {
    color: colour,
    transparent: alpha < 0.999,
    opacity: alpha,
    side: geom.shape === "plane" ? THREE.DoubleSide : THREE.FrontSide,
  };
  const look = materials[geom.material];
  // Lambert for matte primitives: cheapest for software rendering and standalone headsets;
  // Phong where the model asks for highlights or glow.
  const material =
    look === undefined
      ? new THREE.MeshLambertMaterial(common)
      : new THREE.MeshPhongMaterial({
          ...common,
          specular: new THREE.Color(look.specular, look.specular, look.specular),
          shininess: Math.max(1, look.shininess * SHININESS_SCALE),
          emissive: colour.clone().multiplyScalar(look.emission),
          map: look.texture === null ? null : textureFor(look.texture),
        });
  cache.set(key, material);
  return material;
}

interface BatchedPart {
  batch: THREE.BatchedMesh;
  instance: number;
}

export class WorldModel {
  /** Rotated z-up → y-up; everything the server describes lives under it. */
  readonly root = new THREE.Group();
  readonly bodies = new Map<string, THREE.Group>();
  /** Dynamic bodies in State pose order. */
  private dynamic: (THREE.Group | undefined)[] = [];
  /** Where the robot head camera sits (child of the head body, looking along its +x). */
  readonly headCamera = new THREE.Object3D();
  private headBodyName = "";
  private readonly targetMarkers: THREE.Mesh[] = [];
  private readonly materials = new Map<string, THREE.Material>();
  private readonly staticMeshes: THREE.Mesh[] = [];
  private readonly batches: THREE.BatchedMesh[] = [];
  /** Each moving body's instances in the batches, by its dynamic index. */
  private parts: BatchedPart[][] = [];
  private readonly partsByBody = new Map<string, BatchedPart[]>();

  constructor() {
    this.root.name = "world";
    this.root.quaternion.copy(WORLD_TO_THREE);
    // Camera basis in the head body: x_cam = -y, y_cam = +z, z_cam = -x (looks along +x).
    this.headCamera.position.set(HEAD_CAMERA_OFFSET, 0, 0);
    this.headCamera.quaternion.setFromRotationMatrix(
      new THREE.Matrix4().makeBasis(
        new THREE.Vector3(0, -1, 0),
        new THREE.Vector3(0, 0, 1),
        new THREE.Vector3(-1, 0, 0),
      ),
    );
    for (const colour of [0x4fa3ff, 0xff7a4f]) {
      const marker = new THREE.Mesh(
        new THREE.SphereGeometry(0.025, 12, 8),
        new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: 0.55 }),
      );
      marker.visible = false;
      marker.name = "tcp_target";
      this.targetMarkers.push(marker);
    }
  }

  get isEmpty(): boolean {
    return this.bodies.size === 0;
  }

  get headBody(): THREE.Group | undefined {
    return this.bodies.get(this.headBodyName);
  }

  /** Replace everything drawn with the bodies of `scene`. */
  build(scene: Scene): void {
    this.clear();
    this.headBodyName = scene.head_camera_body;
    let maxIndex = -1;
    const fixed = new Map<THREE.Material, THREE.BufferGeometry[]>();
    const moving = new Map<THREE.Material, { body: string; geometry: THREE.BufferGeometry }[]>();
    for (const body of scene.bodies) {
      const group = this.buildBody(body, scene.materials, body.dynamic ? null : fixed, moving);
      this.root.add(group);
      this.bodies.set(body.name, group);
      if (body.dynamic) maxIndex = Math.max(maxIndex, body.index);
    }
    this.batchMoving(moving);
    // Everything that never moves is drawn as one mesh per material (fewer draw calls:
    // software-rendered browsers and standalone headsets both care).
    for (const [material, geometries] of fixed) {
      const merged = mergeGeometries(geometries, false);
      for (const g of geometries) g.dispose();
      if (merged === null) continue;
      const mesh = new THREE.Mesh(merged, material);
      mesh.name = "static";
      mesh.matrixAutoUpdate = false;
      this.staticMeshes.push(mesh);
      this.root.add(mesh);
    }
    this.dynamic = new Array<THREE.Group | undefined>(maxIndex + 1).fill(undefined);
    this.parts = Array.from({ length: maxIndex + 1 }, () => []);
    for (const body of scene.bodies) {
      if (!body.dynamic) continue;
      this.dynamic[body.index] = this.bodies.get(body.name);
      this.parts[body.index] = this.partsByBody.get(body.name) ?? [];
      const group = this.bodies.get(body.name);
      if (group !== undefined) this.placeParts(this.parts[body.index] ?? [], group);
    }
    this.headBody?.add(this.headCamera);
    for (const marker of this.targetMarkers) this.root.add(marker);
  }

  /** Move the dynamic bodies (State.poses / a replay frame, in index order). */
  applyPoses(poses: readonly Pose[]): void {
    const n = Math.min(poses.length, this.dynamic.length);
    for (let i = 0; i < n; i += 1) {
      const group = this.dynamic[i];
      const pose = poses[i];
      if (group !== undefined && pose !== undefined) {
        applyPose(group, pose);
        this.placeParts(this.parts[i] ?? [], group);
      }
    }
  }

  /** Show where each arm is asked to be while it follows its controller. */
  applyTargets(targets: readonly Pose[] | null, following: readonly boolean[] | null): void {
    this.targetMarkers.forEach((marker, i) => {
      const pose = targets?.[i];
      const on = following?.[i] === true && pose !== undefined;
      marker.visible = on;
      if (on) applyPose(marker, pose);
    });
  }

  /** Hide the robot's own head (it would fill a first-person view). */
  setHeadVisible(visible: boolean): void {
    for (const part of this.partsByBody.get(this.headBodyName) ?? []) part.batch.setVisibleAt(part.instance, visible);
  }

  /** World (z-up) pose of a body as last drawn, or null. */
  bodyPose(name: string): Pose | null {
    const group = this.bodies.get(name);
    if (group === undefined) return null;
    const p = group.position;
    const q = group.quaternion;
    return [p.x, p.y, p.z, q.w, q.x, q.y, q.z];
  }

  /** A body's group (its pose); its geoms go, by material, into `fixed` in the world
   * frame (a static body: `fixed` given) or into `moving` in the body's frame. */
  private buildBody(
    body: BodyDescription,
    materials: readonly MaterialDescription[],
    fixed: Map<THREE.Material, THREE.BufferGeometry[]> | null,
    moving: Map<THREE.Material, { body: string; geometry: THREE.BufferGeometry }[]>,
  ): THREE.Group {
    const group = new THREE.Group();
    group.name = body.name;
    applyPose(group, body.pose);
    group.updateMatrix();
    for (const geom of body.geoms) {
      const geometry = geometryFor(geom);
      if (geometry === null || geom.rgba[3] <= 0.001) continue;
      const material = materialFor(geom, materials, this.materials);
      const local = new THREE.Matrix4().compose(
        new THREE.Vector3(geom.pos[0], geom.pos[1], geom.pos[2]),
        new THREE.Quaternion(geom.quat[1], geom.quat[2], geom.quat[3], geom.quat[0]),
        new THREE.Vector3(1, 1, 1),
      );
      if (fixed === null) {
        geometry.applyMatrix4(local);
        const list = moving.get(material) ?? [];
        list.push({ body: body.name, geometry });
        moving.set(material, list);
        continue;
      }
      geometry.applyMatrix4(new THREE.Matrix4().multiplyMatrices(group.matrix, local));
      const list = fixed.get(material) ?? [];
      list.push(geometry);
      fixed.set(material, list);
    }
    return group;
  }

  /** One BatchedMesh per material for the moving bodies' geoms (body frame each). */
  private batchMoving(moving: Map<THREE.Material, { body: string; geometry: THREE.BufferGeometry }[]>): void {
    for (const [material, items] of moving) {
      let vertices = 0;
      let indices = 0;
      for (const { geometry } of items) {
        vertices += geometry.getAttribute("position").count;
        indices += geometry.getIndex()?.count ?? 0;
      }
      const batch = new THREE.BatchedMesh(items.length, vertices, indices, material);
      batch.name = "moving";
      batch.frustumCulled = false; // its instances move every frame
      batch.sortObjects = false;
      for (const { body, geometry } of items) {
        const instance = batch.addInstance(batch.addGeometry(geometry));
        geometry.dispose();
        const parts = this.partsByBody.get(body) ?? [];
        parts.push({ batch, instance });
        this.partsByBody.set(body, parts);
      }
      this.batches.push(batch);
      this.root.add(batch);
    }
  }

  /** Put a body's instances where its group is (root frame). */
  private placeParts(parts: readonly BatchedPart[], group: THREE.Group): void {
    if (parts.length === 0) return;
    group.updateMatrix();
    for (const part of parts) part.batch.setMatrixAt(part.instance, group.matrix);
  }

  private clear(): void {
    for (const group of this.bodies.values()) {
      group.traverse((object) => {
        if (object instanceof THREE.Mesh) (object.geometry as THREE.BufferGeometry).dispose();
      });
      this.root.remove(group);
    }
    for (const mesh of this.staticMeshes) {
      mesh.geometry.dispose();
      this.root.remove(mesh);
    }
    this.staticMeshes.length = 0;
    for (const batch of this.batches) {
      batch.dispose();
      this.root.remove(batch);
    }
    this.batches.length = 0;
    this.parts = [];
    this.partsByBody.clear();
    for (const material of this.materials.values()) {
      if (material instanceof THREE.MeshPhongMaterial) material.map?.dispose();
      material.dispose();
    }
    this.materials.clear();
    this.bodies.clear();
    this.dynamic = [];
    this.headCamera.removeFromParent();
  }
}
