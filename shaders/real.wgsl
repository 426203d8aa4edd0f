// The float type `Real` of the kernels that compute in either precision: shaders/real32.wgsl
// (f32, WGSL's own builtins) or, with the feature F64, shaders/real64.wgsl (f64, with the
// functions f64 lacks on Vulkan built from checked operations). The two define the same names in
// the same order; a kernel imports this module, and its declaration in shaders/kernels.json says
// which precision it is.
#if F64
#import real64
#else
#import real32
#endif
