// The WGSL modules the page runs, from the project's shaders/ at build time, joined in the
// order src/gpu/shaders.rs joins them (with "\n"): TRACE_MODULE, PATH_MODULE and
// JULIA2D_MODULE in f32 (WebGPU has no f64).

import algebra from '../../shaders/algebra.wgsl?raw';
import bsdf from '../../shaders/bsdf.wgsl?raw';
import environment from '../../shaders/environment.wgsl?raw';
import ggxAlbedo from '../../shaders/ggx_albedo.wgsl?raw';
import julia2d from '../../shaders/julia2d.wgsl?raw';
import light from '../../shaders/light.wgsl?raw';
import medium from '../../shaders/medium.wgsl?raw';
import path from '../../shaders/path.wgsl?raw';
import real32 from '../../shaders/real32.wgsl?raw';
import sobol from '../../shaders/sobol.wgsl?raw';
import trace from '../../shaders/trace.wgsl?raw';

/// The tracer in f32 (TRACE_MODULE): the prelude, quaternion arithmetic, the kernel, the
/// environment map.
export const TRACE_MODULE = [real32, algebra, trace, environment].join('\n');
/// The path tracer in f32 (PATH_MODULE): the tracer's module, the material and its albedo
/// tables, the light, the fog's medium, the sampler, then the path kernel.
export const PATH_MODULE = [
  real32,
  algebra,
  trace,
  environment,
  bsdf,
  ggxAlbedo,
  light,
  medium,
  sobol,
  path,
].join('\n');
/// The 2D Julia view in f32 (JULIA2D_MODULE).
export const JULIA2D_MODULE = [real32, julia2d].join('\n');
