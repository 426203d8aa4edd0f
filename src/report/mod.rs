//! Reports on accuracy and stability: the stiff and extreme case suite (`stability`) and the
//! work-precision sweep (`work_precision`), and how the estimate fares as the algebra grows
//! (`dimensions`).

pub mod dimensions;
pub mod stability;
pub mod work_precision;
