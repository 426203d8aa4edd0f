//! The memory a whole-image job would hold, checked against the host's before anything is
//! allocated: a PNG, a denoise or a merge that cannot fit is refused (exit 2, with the bytes it
//! would need) rather than left to the allocator. Streamed work, whose memory is bounded by a
//! band, is never refused.

pub use crate::error::human;
use crate::error::{Error, Result};

/// Overrides the memory qjulia takes to be available, in bytes (tests, and a user who wants a
/// lower ceiling than the host's).
pub const MEMORY_LIMIT_VAR: &str = "QJULIA_MEMORY_LIMIT";

/// A whole [`crate::Frame`] with every AOV, in host memory: colour, depth, steps, samples, M2
/// and the view cosine (4 bytes each), the linear mean, albedo, normal, specular light and the
/// noisy mean (12 each).
pub const FRAME_BYTES_PER_PIXEL: u64 = 6 * 4 + 5 * 12;

/// The whole-image EXR of `--hdr` ([`crate::hdr::HdrImage`]) until it is written, with the
/// noisy and the specular layers: 19 float32 channels, and the view cosine the reflectance is
/// made of.
pub const HDR_BYTES_PER_PIXEL: u64 = 20 * 4;

/// The denoiser's buffers beside the frame ([`crate::denoise`]): the illumination, the guide
/// and a pass's output (16 bytes each), the albedo divided out and the denoised image (12
/// each), and the colour made of it (4).
pub const DENOISE_BYTES_PER_PIXEL: u64 = 3 * 16 + 2 * 12 + 4;

/// The process's resident memory in bytes (Linux: /proc/self/statm, in 4 KiB pages; None
/// elsewhere).
pub fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}

/// The bytes a whole-image job may hold: `QJULIA_MEMORY_LIMIT` where set, else the host's
/// available memory (Linux's `MemAvailable`), else None (not known: nothing is refused).
pub fn available() -> Option<u64> {
    if let Some(limit) = std::env::var(MEMORY_LIMIT_VAR)
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
    {
        return Some(limit);
    }
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    meminfo_available(&meminfo)
}

/// `MemAvailable` of a /proc/meminfo text, in bytes.
fn meminfo_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Ok when `needed` bytes fit in `available` (None: unknown, so Ok); else the error that says
/// what would not fit (`what`, e.g. "render's 65536x65536 image") and the bytes.
pub fn check_within(what: &str, needed: u64, available: Option<u64>) -> Result<()> {
    match available {
        Some(available) if needed > available => Err(Error::Memory {
            what: what.to_string(),
            needed,
            available,
        }),
        _ => Ok(()),
    }
}

/// [`check_within`] the memory [`available`] now.
pub fn check(what: &str, needed: u64) -> Result<()> {
    check_within(what, needed, available())
}

/// Pixels per band of a streamed render: 4 Mpixel (16 MiB per output array), or
/// `QJULIA_BAND_PIXELS` (at least 64) to trade memory for dispatch count.
pub fn band_pixels() -> u64 {
    std::env::var("QJULIA_BAND_PIXELS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
        .map_or(1 << 22, |n| n.max(64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_gives_the_available_bytes() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   20000000 kB\n";
        assert_eq!(meminfo_available(text), Some(20_000_000 * 1024));
        assert_eq!(meminfo_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn a_job_over_the_limit_is_refused_with_its_bytes() {
        assert!(check_within("x", 10, Some(10)).is_ok());
        assert!(check_within("x", 10, None).is_ok());
        let e = check_within("render's 8x8 image", 11, Some(10)).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert_eq!(
            e.to_string(),
            "render's 8x8 image would need 11 bytes (11 bytes) of memory, more than the 10 bytes \
             (10 bytes) available"
        );
    }

    #[test]
    fn bytes_read_as_a_person_reads_them() {
        assert_eq!(human(900), "900 bytes");
        assert_eq!(human(5 << 30), "5.0 GiB");
        assert_eq!(human(3 << 19), "1.5 MiB");
    }
}
