// The operator's two controllers drawn where they are in the headset: a small box each
// (left blue, right orange), lit while its grip is held.

import * as THREE from "three";
import type { Pose } from "../protocol";

interface Tracked {
  pose: Pose | null;
  grip: number;
}

function controllerMarker(colour: number): THREE.Mesh {
  const mesh = new THREE.Mesh(
    new THREE.BoxGeometry(0.05, 0.03, 0.1),
    new THREE.MeshStandardMaterial({ color: colour, roughness: 0.5 }),
  );
  mesh.visible = false;
  return mesh;
}

export class ControllerMarkers {
  readonly meshes: readonly THREE.Mesh[] = [controllerMarker(0x4fa3ff), controllerMarker(0xff7a4f)];

  /** Show each hand where it is (hidden while it is not tracked). */
  update(left: Tracked, right: Tracked): void {
    [left, right].forEach((hand, i) => {
      const marker = this.meshes[i];
      if (marker === undefined) return;
      marker.visible = hand.pose !== null;
      if (hand.pose !== null) {
        marker.position.set(hand.pose[0], hand.pose[1], hand.pose[2]);
        marker.quaternion.set(hand.pose[4], hand.pose[5], hand.pose[6], hand.pose[3]);
        (marker.material as THREE.MeshStandardMaterial).emissive.setHex(hand.grip >= 0.5 ? 0x333333 : 0);
      }
    });
  }

  hide(): void {
    for (const m of this.meshes) m.visible = false;
  }
}
