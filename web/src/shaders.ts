// The WGSL modules the page runs, from the project's shaders/ at build time, joined in the
// order src/gpu/shaders.rs joins them (with "\n").

import algebra from '../../shaders/algebra.wgsl?raw';
import real32 from '../../shaders/real32.wgsl?raw';
import trace from '../../shaders/trace.wgsl?raw';

/// The tracer in f32 (TRACE_MODULE): the prelude, quaternion arithmetic, the kernel.
export const TRACE_MODULE = [real32, algebra, trace].join('\n');
