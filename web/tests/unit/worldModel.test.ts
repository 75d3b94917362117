import * as THREE from "three";
import { describe, expect, it } from "vitest";
import type { BodyDescription, GeomDescription, MaterialDescription, Scene } from "../../src/protocol";
import { WorldModel, materialFor, textureFor } from "../../src/scene/worldModel";

/** Base64 of raw bytes, as the server sends a texture's pixels. */
function base64(bytes: number[]): string {
  return btoa(String.fromCharCode(...bytes));
}

const CHECKER: MaterialDescription = {
  name: "floor_mat",
  specular: 0.15,
  shininess: 0.2,
  emission: 0,
  // 2 x 2 pixels: red, green / green, red
  texture: { width: 2, height: 2, rgb: base64([255, 0, 0, 0, 255, 0, 0, 255, 0, 255, 0, 0]), repeat: [8, 4] },
};
const SIGNAL: MaterialDescription = { name: "signal", specular: 0.3, shininess: 0.5, emission: 0.8, texture: null };

function geom(shape: string, material: number, rgba: [number, number, number, number]): GeomDescription {
  return { shape, size: [0.1, 0.1, 0.1], pos: [0, 0, 0], quat: [1, 0, 0, 0], rgba, material };
}

describe("the scene's materials", () => {
  it("turns a texture's RGB pixels into a repeating RGBA texture", () => {
    const texture = textureFor(CHECKER.texture!);
    const data = texture.image.data as Uint8Array;
    expect([texture.image.width, texture.image.height]).toEqual([2, 2]);
    expect(Array.from(data.slice(0, 8))).toEqual([255, 0, 0, 255, 0, 255, 0, 255]);
    expect([texture.repeat.x, texture.repeat.y]).toEqual([8, 4]);
    expect(texture.wrapS).toBe(THREE.RepeatWrapping);
  });

  it("shades a geom as its MuJoCo material says, and one without a material matte", () => {
    const cache = new Map<string, THREE.Material>();
    const materials = [CHECKER, SIGNAL];
    const floor = materialFor(geom("plane", 0, [1, 1, 1, 1]), materials, cache);
    expect(floor).toBeInstanceOf(THREE.MeshPhongMaterial);
    const phong = floor as THREE.MeshPhongMaterial;
    expect(phong.map).not.toBeNull();
    expect(phong.specular.r).toBeCloseTo(0.15);
    expect(phong.shininess).toBeCloseTo(0.2 * 128);
    const strip = materialFor(geom("box", 1, [0.25, 0.8, 1, 1]), materials, cache) as THREE.MeshPhongMaterial;
    expect(strip.emissive.g).toBeCloseTo(0.8 * strip.color.g);
    expect(materialFor(geom("box", -1, [0.5, 0.5, 0.5, 1]), materials, cache)).toBeInstanceOf(THREE.MeshLambertMaterial);
    // Geoms sharing a material and a colour share a three.js material (and a draw call).
    expect(materialFor(geom("box", 1, [0.25, 0.8, 1, 1]), materials, cache)).toBe(strip);
    expect(materialFor(geom("box", 1, [1, 0, 0, 1]), materials, cache)).not.toBe(strip);
  });

  it("draws everything that never moves as one mesh per material", () => {
    const body = (name: string, geoms: GeomDescription[]): BodyDescription => ({
      name,
      index: -1,
      dynamic: false,
      pose: [0, 0, 0, 1, 0, 0, 0],
      geoms,
    });
    const scene: Scene = {
      type: "scene",
      head_camera_body: "head",
      materials: [CHECKER, SIGNAL],
      bodies: [
        body("floor", [geom("plane", 0, [1, 1, 1, 1])]),
        body("a", [geom("box", 1, [0.25, 0.8, 1, 1]), geom("box", 1, [0.25, 0.8, 1, 1])]),
        body("b", [geom("box", 1, [0.25, 0.8, 1, 1]), geom("sphere", -1, [0.3, 0.3, 0.3, 1])]),
      ],
    };
    const world = new WorldModel();
    world.build(scene);
    const meshes = world.root.children.filter((c) => c instanceof THREE.Mesh && c.name === "static");
    expect(meshes).toHaveLength(3); // the floor, the three signal boxes, the matte sphere
  });
});
