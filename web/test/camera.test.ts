// The camera controller's twin (src/camera.ts) against the Rust one (src/explore/camera.rs):
// test/fixtures/camera.json holds drags, pans and wheel turns from four cameras (the default,
// two presets, a tilted `up`), and drags and wheel turns over the 2D view, each with the camera
// (or 2D view) the library left after it (made by tests/architecture/web.rs, held fresh there). Replayed
// here, every number must be the same f64, bit for bit.

import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, test } from 'vitest';
import * as camera from '../src/camera';
import { SCHEMA } from '../src/scene';
import type { V3 } from '../src/vector';

interface Cam {
  eye: V3;
  target: V3;
  fov_y_degrees: number;
}

const fixture = JSON.parse(readFileSync(join(import.meta.dirname, 'fixtures/camera.json'), 'utf8')) as {
  constants: Record<string, number>;
  scripts: { name: string; start: { up: V3; camera: Cam }; steps: { op: [string, ...number[]]; camera: Cam }[] }[];
  view2d: {
    start: { center: [number, number]; extent: number };
    steps: { op: [string, number, number, number | [number, number] | null]; center: [number, number]; extent: number }[];
  };
};

const widest = SCHEMA.keys.find((k) => k.path === 'view2d.extent')!.slider!.max;

describe('the camera', () => {
  test('the constants are the library\u2019s', () => {
    const { constants } = fixture;
    expect(camera.ORBIT_PER_POINT).toBe(constants.ORBIT_PER_POINT);
    expect(camera.ZOOM_PER_POINT).toBe(constants.ZOOM_PER_POINT);
    expect(camera.MIN_DISTANCE).toBe(constants.MIN_DISTANCE);
    expect(camera.MAX_DISTANCE).toBe(constants.MAX_DISTANCE);
    expect(camera.WIDE_FOV_DEGREES).toBe(constants.WIDE_FOV_DEGREES);
    expect(camera.MIN_FOV_DEGREES).toBe(constants.MIN_FOV_DEGREES);
    expect(camera.MIN_EXTENT).toBe(constants.MIN_EXTENT);
  });

  // Each move starts from the camera the library left before it, so that a difference cannot
  // grow. The arithmetic is the library's, operation for operation, and most moves agree bit
  // for bit (228 of the 240 here, 79 of the 80 in 2D; every pan and 2D drag); the rest differ in the last bits only where a move calls
  // exp, sin, cos, atan or acos, which V8 (fdlibm) and Rust (glibc) round differently: at most 4
  // units in the last place measured, 8 allowed.
  test.each(fixture.scripts.map((s) => [s.name, s] as const))('from %s', (_, script) => {
    let before = script.start.camera;
    let exact = 0;
    for (const [k, step] of script.steps.entries()) {
      const cam: camera.Camera = {
        eye: [...before.eye],
        target: [...before.target],
        up: script.start.up,
        fovYDegrees: before.fov_y_degrees,
      };
      const [op, a, b, c] = step.op as [string, number, number, number];
      if (op === 'orbit') camera.dragOrbit(cam, a, b);
      else if (op === 'pan') camera.dragPan(cam, a, b, c);
      else camera.wheelZoom(cam, a);
      const got = [...cam.eye, ...cam.target, cam.fovYDegrees];
      const want = [...step.camera.eye, ...step.camera.target, step.camera.fov_y_degrees];
      const worst = Math.max(...got.map((x, i) => ulps(x, want[i])));
      expect({ k, op, worst: Math.min(worst, 9) }).toEqual({ k, op, worst: Math.min(worst, 8) });
      if (op === 'pan') expect({ k, op, got }).toEqual({ k, op, got: want });
      exact += Number(worst === 0);
      before = step.camera;
    }
    console.log(`${script.name}: ${exact} of ${script.steps.length} moves bit for bit`);
  });

  test('the 2D view', () => {
    let before = fixture.view2d.start;
    let exact = 0;
    for (const [k, step] of fixture.view2d.steps.entries()) {
      const v: camera.View2d = { center: [...before.center], extent: before.extent };
      const [op, a, b, c] = step.op;
      // ["drag", dx, dy, width] or ["wheel", scroll, width, from the centre or null]
      if (op === 'drag') camera.drag2d(v, a, b, c as number);
      else camera.wheelZoom2d(v, a, b, c as [number, number] | null, widest);
      const got = [...v.center, v.extent];
      const want = [...step.center, step.extent];
      const worst = Math.max(...got.map((x, i) => ulps(x, want[i])));
      expect({ k, op, worst: Math.min(worst, 9) }).toEqual({ k, op, worst: Math.min(worst, 8) });
      if (op === 'drag') expect({ k, got }).toEqual({ k, got: want });
      exact += Number(worst === 0);
      before = step;
    }
    console.log(`the 2D view: ${exact} of ${fixture.view2d.steps.length} moves bit for bit`);
  });
});

/// How many f64s lie between a and b (0: the same bits).
function ulps(a: number, b: number): number {
  if (Object.is(a, b)) return 0;
  const bits = new BigInt64Array(new Float64Array([a, b]).buffer);
  const ordered = bits.map((i) => (i < 0n ? -(i & 0x7fffffffffffffffn) : i));
  const d = ordered[0] - ordered[1];
  return Number(d < 0n ? -d : d);
}
