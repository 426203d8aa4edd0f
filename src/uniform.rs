//! The kernels' uniforms, each declared once: `uniform!` takes one table of fields (name, kind,
//! how the scene gives it) and makes the host parameters (`TraceParams<F>`, which the CPU twin
//! reads), their `#[repr(C)]` bytemuck images in f32 and f64 (what the GPU reads), and a static
//! [`Layout`] of each image (names, offsets, sizes, WGSL types) that the tests hold against
//! naga's reflection of the WGSL struct and `qjulia gpu-params --json` prints.
//!
//! A field's kind is one of `Real`, `Vec2`, `Vec3`, `Hyper` (host `F`, `Vec2<F>`, `Vec3<F>`,
//! `Hyper<F>`; WGSL `Real`, `vec2<Real>`, `vec3<Real>`, `array<vec4<Real>, 4>`), `u32`, `bool`
//! (WGSL u32: 0 or 1) or a scene enum with a `code()` (WGSL u32: the code). The per-dispatch
//! fields (the band, where it lands, the samples it adds) are the image's alone: the host
//! parameters describe the whole picture.
//!
//! The images are laid out by WGSL's rules for uniforms without a byte of padding inside: each
//! field must start where WGSL would put it (a multiple of its WGSL alignment right after the
//! one before), which is checked when the crate compiles; the padding that rounds the size up
//! to the struct's alignment is added at the end (`_pad`, the host's alone).

use serde::Serialize;

/// One member of a uniform struct as WGSL lays it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct FieldLayout {
    pub name: &'static str,
    /// Bytes from the start of the struct.
    pub offset: usize,
    /// Bytes the member's type takes (a vec3's 3 scalars: the scalar after it fills its slot).
    pub size: usize,
    /// The WGSL type: `f32`, `f64`, `u32`, `vec2<f32>`, `vec3<f64>`, `array<vec4<f32>, 4>`, ...
    #[serde(rename = "type")]
    pub ty: &'static str,
    /// Set per dispatch (the band, where it lands, its samples), not by the scene.
    pub per_dispatch: bool,
}

/// A uniform struct as WGSL lays it out, in one precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Layout {
    /// The struct's name in the WGSL source.
    pub name: &'static str,
    /// Bytes, a multiple of `align`.
    pub size: usize,
    /// WGSL's alignment of the struct: the largest of its members'.
    pub align: usize,
    /// The members in order.
    pub fields: &'static [FieldLayout],
}

impl Layout {
    /// The member called `name`.
    pub fn field(&self, name: &str) -> Option<&FieldLayout> {
        self.fields.iter().find(|f| f.name == name)
    }
}

/// The u32s of padding that round a struct of these members (sizes and WGSL alignments, in
/// order) up to its alignment; fails to compile where a member does not start where WGSL would
/// put it.
pub const fn pad_words(sizes: &[usize], aligns: &[usize]) -> usize {
    let (mut end, mut align, mut k) = (0, 1, 0);
    while k < sizes.len() {
        assert!(
            end % aligns[k] == 0,
            "a uniform field does not start at its WGSL alignment: reorder the table"
        );
        end += sizes[k];
        if aligns[k] > align {
            align = aligns[k];
        }
        k += 1;
    }
    (end.next_multiple_of(align) - end) / 4
}

/// The largest of these alignments.
pub const fn max_align(aligns: &[usize]) -> usize {
    let (mut align, mut k) = (1, 0);
    while k < aligns.len() {
        if aligns[k] > align {
            align = aligns[k];
        }
        k += 1;
    }
    align
}

/// What a field's kind is in expressions: `pack` the image's value of a host value, `wgsl` the
/// WGSL type's name and `align` its WGSL alignment (float `$r`). Its types are [`uniform!`]'s
/// (a derive takes no type macros).
macro_rules! kind {
    (pack Real, $v:expr) => {
        $v
    };
    (pack Vec2, $v:expr) => {{
        let v = $v;
        [v.x, v.y]
    }};
    (pack Vec3, $v:expr) => {{
        let v = $v;
        [v.x, v.y, v.z]
    }};
    (pack Hyper, $v:expr) => {
        $v.map(|q| [q.x, q.y, q.z, q.w])
    };
    (pack u32, $v:expr) => {
        $v
    };
    (pack bool, $v:expr) => {
        $v as u32
    };
    (pack $enum:ident, $v:expr) => {
        $v.code()
    };

    (wgsl Real, $r:ident) => {
        stringify!($r)
    };
    (wgsl Vec2, $r:ident) => {
        concat!("vec2<", stringify!($r), ">")
    };
    (wgsl Vec3, $r:ident) => {
        concat!("vec3<", stringify!($r), ">")
    };
    (wgsl Hyper, $r:ident) => {
        concat!("array<vec4<", stringify!($r), ">, 4>")
    };
    (wgsl $other:ident, $r:ident) => {
        "u32"
    };

    (align Real, $r:ident) => {
        size_of::<$r>()
    };
    (align Vec2, $r:ident) => {
        2 * size_of::<$r>()
    };
    (align Vec3, $r:ident) => {
        4 * size_of::<$r>()
    };
    (align Hyper, $r:ident) => {
        4 * size_of::<$r>()
    };
    (align $other:ident, $r:ident) => {
        4
    };
}
pub(crate) use kind;

/// One uniform, declared once: the host parameters `$host<F>` with `new(scene)` (the setup
/// statements, then each field's value), and its images `$gpu32` (f32) and `$gpu64` (f64) with
/// `new(p, row_offset, row_count)` (the host values packed, then each per-dispatch field's value)
/// and `LAYOUT`. The field order is the WGSL struct's (`$wgsl`): the scene's fields, then the
/// per-dispatch ones.
///
/// The fields are read one at a time (`@field`), each kind giving its host and image types,
/// then everything is written at once (`@write`, `@gpu`).
macro_rules! uniform {
    (
        $(#[$host_meta:meta])*
        pub struct $host:ident<F> for $wgsl:literal;
        $(#[$gpu32_meta:meta])*
        pub struct $gpu32:ident<f32>;
        $(#[$gpu64_meta:meta])*
        pub struct $gpu64:ident<f64>;
        fn new($scene:ident) { $($setup:tt)* }
        fields { $($fields:tt)* }
        per_dispatch $args:tt $dispatch:tt
        $(host_only { $($host_only:tt)* })?
    ) => {
        $crate::uniform::uniform!(@field {
            [$(#[$host_meta])*] $host $wgsl
            [$(#[$gpu32_meta])*] $gpu32 [$(#[$gpu64_meta])*] $gpu64
            $scene { $($setup)* } $args $dispatch { $($($host_only)*)? }
        } [] $($fields)*);
    };

    // One field: [docs] name kind (value) (host type) (f32 image type) (f64 image type).
    (@field $ctx:tt [$($done:tt)*] $(#[$m:meta])* $field:ident: Real = $value:expr, $($rest:tt)*) => {
        $crate::uniform::uniform!(@field $ctx [$($done)*
            { [$(#[$m])*] $field Real ($value) (F) (f32) (f64) }] $($rest)*);
    };
    (@field $ctx:tt [$($done:tt)*] $(#[$m:meta])* $field:ident: Vec2 = $value:expr, $($rest:tt)*) => {
        $crate::uniform::uniform!(@field $ctx [$($done)*
            { [$(#[$m])*] $field Vec2 ($value) ($crate::algebra::Vec2<F>) ([f32; 2]) ([f64; 2]) }]
            $($rest)*);
    };
    (@field $ctx:tt [$($done:tt)*] $(#[$m:meta])* $field:ident: Vec3 = $value:expr, $($rest:tt)*) => {
        $crate::uniform::uniform!(@field $ctx [$($done)*
            { [$(#[$m])*] $field Vec3 ($value) ($crate::algebra::Vec3<F>) ([f32; 3]) ([f64; 3]) }]
            $($rest)*);
    };
    (@field $ctx:tt [$($done:tt)*] $(#[$m:meta])* $field:ident: Hyper = $value:expr, $($rest:tt)*) => {
        $crate::uniform::uniform!(@field $ctx [$($done)*
            { [$(#[$m])*] $field Hyper ($value) ($crate::algebra::Hyper<F>) ([[f32; 4]; 4])
                ([[f64; 4]; 4]) }]
            $($rest)*);
    };
    // u32, bool or a scene enum: the host's type is the kind; the image's a u32.
    (@field $ctx:tt [$($done:tt)*] $(#[$m:meta])* $field:ident: $kind:ident = $value:expr, $($rest:tt)*) => {
        $crate::uniform::uniform!(@field $ctx [$($done)*
            { [$(#[$m])*] $field $kind ($value) ($kind) (u32) (u32) }] $($rest)*);
    };
    (@field $ctx:tt $done:tt) => {
        $crate::uniform::uniform!(@write $ctx $done);
    };

    (@write {
        [$(#[$host_meta:meta])*] $host:ident $wgsl:literal
        [$(#[$gpu32_meta:meta])*] $gpu32:ident [$(#[$gpu64_meta:meta])*] $gpu64:ident
        $scene:ident { $($setup:tt)* }
        ($p:ident, $row_offset:ident, $row_count:ident) {
            $( $(#[$dmeta:meta])* $dfield:ident: u32 = $dvalue:expr, )*
        }
        { $( $(#[$hmeta:meta])* $hfield:ident: $hty:ty = $hvalue:expr, )* }
    } [$( {
        [$(#[$meta:meta])*] $field:ident $kind:ident ($value:expr) ($($host_ty:tt)*)
        ($($ty32:tt)*) ($($ty64:tt)*)
    } )*]) => {
        $(#[$host_meta])*
        pub struct $host<F> {
            $( $(#[$meta])* pub $field: $($host_ty)*, )*
            $( $(#[$hmeta])* pub $hfield: $hty, )*
        }

        impl<F: $crate::algebra::Real> $host<F> {
            /// The parameters of a validated scene, rounded to the precision.
            pub fn new($scene: &$crate::scene::Scene) -> Self {
                $($setup)*
                Self { $( $field: $value, )* $( $hfield: $hvalue, )* }
            }
        }

        $crate::uniform::uniform!(@gpu [$(#[$gpu32_meta])*] $gpu32, f32, $host, $wgsl;
            $( [$(#[$meta])*] $field $kind ($($ty32)*) )*;
            $p, $row_offset, $row_count; $( [$(#[$dmeta])*] $dfield = $dvalue, )*);
        $crate::uniform::uniform!(@gpu [$(#[$gpu64_meta])*] $gpu64, f64, $host, $wgsl;
            $( [$(#[$meta])*] $field $kind ($($ty64)*) )*;
            $p, $row_offset, $row_count; $( [$(#[$dmeta])*] $dfield = $dvalue, )*);
    };

    // A per-dispatch field's size and alignment (a u32).
    (@word $dfield:ident) => { 4 };

    (@gpu [$(#[$gpu_meta:meta])*] $gpu:ident, $r:ident, $host:ident, $wgsl:literal;
        $( [$(#[$meta:meta])*] $field:ident $kind:ident ($($ty:tt)*) )*;
        $p:ident, $row_offset:ident, $row_count:ident;
        $( [$(#[$dmeta:meta])*] $dfield:ident = $dvalue:expr, )*
    ) => {
        $(#[$gpu_meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $gpu {
            $( $(#[$meta])* pub $field: $($ty)*, )*
            $( $(#[$dmeta])* pub $dfield: u32, )*
            /// Rounds the size up to the WGSL struct's alignment (the host's alone).
            pub _pad: [u32; $crate::uniform::pad_words(
                &[$( size_of::<$($ty)*>(), )* $( $crate::uniform::uniform!(@word $dfield), )*],
                &[$( $crate::uniform::kind!(align $kind, $r), )*
                    $( $crate::uniform::uniform!(@word $dfield), )*],
            )],
        }

        impl $gpu {
            /// The layout of WGSL's struct, as the host packs it.
            pub const LAYOUT: $crate::uniform::Layout = $crate::uniform::Layout {
                name: $wgsl,
                size: size_of::<$gpu>(),
                align: $crate::uniform::max_align(&[$( $crate::uniform::kind!(align $kind, $r), )*
                    $( $crate::uniform::uniform!(@word $dfield), )*]),
                fields: &[
                    $( $crate::uniform::FieldLayout {
                        name: stringify!($field),
                        offset: std::mem::offset_of!($gpu, $field),
                        size: size_of::<$($ty)*>(),
                        ty: $crate::uniform::kind!(wgsl $kind, $r),
                        per_dispatch: false,
                    }, )*
                    $( $crate::uniform::FieldLayout {
                        name: stringify!($dfield),
                        offset: std::mem::offset_of!($gpu, $dfield),
                        size: 4,
                        ty: "u32",
                        per_dispatch: true,
                    }, )*
                ],
            };

            /// The uniform of a band of rows [row_offset, row_offset + row_count), with the
            /// per-dispatch fields' defaults for a band-sized output.
            pub fn new($p: &$host<$r>, $row_offset: u32, $row_count: u32) -> Self {
                Self {
                    $( $field: $crate::uniform::kind!(pack $kind, $p.$field), )*
                    $( $dfield: $dvalue, )*
                    _pad: Default::default(),
                }
            }

            /// The bytes the GPU reads.
            pub fn bytes(&self) -> &[u8] {
                bytemuck::bytes_of(self)
            }
        }
    };
}
pub(crate) use uniform;
