//! Buffers of one value per pixel, zeroed, on the operating system's huge pages where it gives
//! them. Such a buffer is fresh memory that the tracer then writes once, and on Linux the first
//! write to each 4 KiB page is a page fault: 19 000 of them for the forest's 1920×1080 G-buffer,
//! a tenth of its time. Asked for huge pages (`MADV_HUGEPAGE`: where transparent huge pages are
//! set to `madvise`, a common default, Linux gives them only where asked), a fault maps 2 MiB at
//! once: the G-buffer 1.07–1.11× and primary rays 1.07–1.15× as fast on the forest
//! (docs/scale.md).

use bytemuck::Zeroable;
use std::ops::Range;

/// The size of a huge page on x86-64 and on aarch64 with 4 KiB pages; elsewhere only the part of
/// the advice the kernel can use is taken.
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
const HUGE_PAGE_BYTES: usize = 2 << 20;

/// `n` zeroed values, their memory marked for huge pages where it spans at least one.
pub(in crate::trace) fn zeroed_pixels<T: Zeroable>(n: usize) -> Vec<T> {
    let mut values: Vec<T> = bytemuck::zeroed_vec(n);
    advise_huge_pages(values.as_mut_ptr().cast(), std::mem::size_of_val(values.as_slice()));
    values
}

/// Asks the kernel to back the whole huge pages within `bytes` bytes from `start` with huge
/// pages. Advice only: where the kernel has none, or refuses, nothing changes.
#[cfg(target_os = "linux")]
fn advise_huge_pages(start: *mut u8, bytes: usize) {
    if let Some(pages) = whole_huge_pages(start as usize, bytes) {
        // SAFETY: the range lies within the allocation of `bytes` bytes at `start`, and
        // MADV_HUGEPAGE only changes how the kernel backs those pages, never their contents.
        unsafe { libc::madvise(pages.start as *mut libc::c_void, pages.len(), libc::MADV_HUGEPAGE) };
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_start: *mut u8, _bytes: usize) {}

/// The addresses of the whole huge pages within `bytes` bytes from `start`, if any.
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
fn whole_huge_pages(start: usize, bytes: usize) -> Option<Range<usize>> {
    let first = start.checked_next_multiple_of(HUGE_PAGE_BYTES)?;
    let end = (start + bytes) / HUGE_PAGE_BYTES * HUGE_PAGE_BYTES;
    (end > first).then_some(first..end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_buffers_are_zeroed_at_every_size() {
        for n in [0, 1, 1000, (HUGE_PAGE_BYTES / 4) * 3 + 5] {
            let values: Vec<u32> = zeroed_pixels(n);
            assert_eq!(values.len(), n);
            assert!(values.iter().all(|&v| v == 0));
        }
    }

    /// The advice covers every whole huge page of the buffer and nothing outside it.
    #[test]
    fn the_advice_covers_the_whole_huge_pages_within_the_buffer() {
        const H: usize = HUGE_PAGE_BYTES;
        assert_eq!(whole_huge_pages(H, H), Some(H..2 * H));
        assert_eq!(whole_huge_pages(H + 1, H), None);
        assert_eq!(whole_huge_pages(H - 1, H + 1), Some(H..2 * H));
        assert_eq!(whole_huge_pages(3 * H + 4096, 5 * H), Some(4 * H..8 * H));
        assert_eq!(whole_huge_pages(0, 0), None);
        assert_eq!(whole_huge_pages(usize::MAX - 10, 5), None);
        for start in (0..6 * H).step_by(H / 3 + 4096) {
            for bytes in (0..4 * H).step_by(H / 5 + 64) {
                match whole_huge_pages(start, bytes) {
                    Some(pages) => {
                        assert!(pages.start % H == 0 && pages.end % H == 0 && !pages.is_empty());
                        assert!(start <= pages.start && pages.end <= start + bytes);
                        assert!(pages.start - start < H && start + bytes - pages.end < H);
                    }
                    None => assert!(start.next_multiple_of(H) + H > start + bytes),
                }
            }
        }
    }
}
