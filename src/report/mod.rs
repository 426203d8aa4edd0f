//! Reports on accuracy and stability: the stiff and extreme case suite (`stability`) and the
//! work-precision sweep (`work_precision`).

pub mod stability;
pub mod work_precision;
