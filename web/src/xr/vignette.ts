// The tunnel vignette: a dark ring close in front of the eyes whose opacity follows the
// base's motion (see comfort.ts); the centre stays clear. Its blackout covers the whole
// view (while a snap turn turns the base, see snapTurn.ts).

import * as THREE from "three";

export class Vignette {
  readonly mesh: THREE.Mesh;
  private readonly material: THREE.MeshBasicMaterial;
  private readonly cover: THREE.Mesh;
  strength = 0;
  blackedOut = false;

  constructor() {
    const size = 256;
    const canvas = document.createElement("canvas");
    canvas.width = size;
    canvas.height = size;
    const c = canvas.getContext("2d");
    if (c === null) throw new Error("no 2D canvas context for the vignette");
    const g = c.createRadialGradient(size / 2, size / 2, size * 0.18, size / 2, size / 2, size / 2);
    g.addColorStop(0, "rgba(0,0,0,0)");
    g.addColorStop(0.55, "rgba(0,0,0,0.85)");
    g.addColorStop(1, "rgba(0,0,0,1)");
    c.fillStyle = g;
    c.fillRect(0, 0, size, size);
    const texture = new THREE.CanvasTexture(canvas);
    this.material = new THREE.MeshBasicMaterial({ map: texture, transparent: true, depthTest: false, opacity: 0 });
    this.mesh = new THREE.Mesh(new THREE.PlaneGeometry(0.5, 0.5), this.material);
    this.mesh.name = "comfort_vignette";
    this.mesh.position.set(0, 0, -0.12);
    this.mesh.renderOrder = 20;
    this.mesh.visible = false;
    this.cover = new THREE.Mesh(
      new THREE.PlaneGeometry(0.5, 0.5),
      new THREE.MeshBasicMaterial({ color: 0x000000, depthTest: false }),
    );
    this.cover.name = "comfort_blackout";
    this.cover.renderOrder = 21;
    this.cover.visible = false;
    this.mesh.add(this.cover);
  }

  set(strength: number, blackout = false): void {
    this.strength = strength;
    this.blackedOut = blackout;
    this.material.opacity = strength;
    this.cover.visible = blackout;
    this.mesh.visible = strength > 0.01 || blackout;
  }
}
