//! The vector forms the walks run with here, chosen at run time: whether the 8-lane node test and
//! packets run at all (`wide_available`: AVX2 and FMA), and which instruction set the packet walk
//! (packet.rs) is compiled for: AVX2 with FMA, or AVX-512 (F, VL, BW, DQ, with BMI1/2, LZCNT and
//! POPCNT) where the processor has it. The walk's functions are all `#[inline(always)]` with no
//! target features of their own (stable Rust allows no `inline(always)` beside one): each query
//! runs them inside one of two entry points (`in_packet_isa`), one compiled for each set, so the
//! same source is compiled twice. Called outside it, they would make each vector operation a call.
//! With AVX-512 the compiler has 32 vector registers, mask registers and broadcast operands for the
//! same 8-lane operations; the operations, and so the answers, are the same bit for bit (IEEE
//! arithmetic either way, and Rust never fuses a multiply and an add on its own: the node test's
//! fused operations are written as such). With AVX-512 every query walks sixteen rays to a packet
//! (`L16`, `PacketQuery::SixteenLanes`): on the 200K forest at 1920×1080, one thread, shadow rays
//! ran 1.21×, primary rays in tiles of 4×4 1.12× and the G-buffer 1.09× as fast as in packets of
//! eight compiled for AVX2 (docs/scale.md). Packets of eight remain for what is left over (a batch
//! of at most eight rays, or one whose sixteen rays cannot share a walk); closest hits take the
//! AVX-512 compilation for them too, which ran primary rays at 1.03× the AVX2 one's rate, but
//! shadow rays at 0.93× and the certified G-buffer walk at 0.91×, which so keep AVX2.

/// Whether the 8-lane test may run: the processor has AVX2 and FMA (the packets' node test fuses
/// a multiply and a subtraction), and `SHADOWTRUTH_NODE_TEST` is not `portable` (which keeps the
/// portable form, for comparing the two). Decided once per process.
pub(in crate::trace) fn wide_available() -> bool {
    static WIDE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WIDE.get_or_init(|| {
        let forced_portable = std::env::var("SHADOWTRUTH_NODE_TEST").is_ok_and(|v| v == "portable");
        !forced_portable
            && is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("fma")
            && is_x86_feature_detected!("fma")
    })
}

/// An instruction set the packet walk is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::trace) enum PacketIsa {
    Avx2,
    Avx512,
}

/// The set the packet walk runs with here, or `None` where it does not run (no AVX2, or
/// `SHADOWTRUTH_NODE_TEST=portable`). `SHADOWTRUTH_NODE_TEST=avx2` keeps the AVX2 form on a
/// processor with AVX-512, for comparing the two. Decided once per process.
pub(in crate::trace) fn packet_isa() -> Option<PacketIsa> {
    static ISA: std::sync::OnceLock<Option<PacketIsa>> = std::sync::OnceLock::new();
    *ISA.get_or_init(|| {
        if !wide_available() {
            return None;
        }
        let avx2_only = std::env::var("SHADOWTRUTH_NODE_TEST").is_ok_and(|v| v == "avx2");
        let avx512 = is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512dq")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("bmi2")
            && is_x86_feature_detected!("lzcnt")
            && is_x86_feature_detected!("popcnt");
        Some(if avx512 && !avx2_only { PacketIsa::Avx512 } else { PacketIsa::Avx2 })
    })
}

/// What a packet walk is for: each runs compiled for the set that runs it fastest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::trace) enum PacketQuery {
    /// Closest hits alone (primary rays), eight at a time: AVX-512 where the processor has it.
    ClosestHits,
    /// Closest hits with their certificates (the G-buffer), eight at a time: AVX2.
    CertifiedHits,
    /// Shadow rays, eight at a time: AVX2.
    Shadows,
    /// Any query, sixteen rays at a time: AVX-512 only.
    SixteenLanes,
}

/// The set the packet walk of `query` runs with here, or `None` where packets do not run
/// (`packet_isa`).
pub(in crate::trace) fn packet_isa_for(query: PacketQuery) -> Option<PacketIsa> {
    match query {
        PacketQuery::ClosestHits => packet_isa(),
        PacketQuery::CertifiedHits | PacketQuery::Shadows => packet_isa().map(|_| PacketIsa::Avx2),
        PacketQuery::SixteenLanes => packet_isa().filter(|&isa| isa == PacketIsa::Avx512),
    }
}

/// Runs `walk` compiled for `isa` (from `packet_isa`, so that the processor has it): the packet
/// walk's functions inline into it and take its instruction set.
#[inline(always)]
pub(in crate::trace) fn in_packet_isa<R>(isa: PacketIsa, walk: impl FnOnce() -> R) -> R {
    match isa {
        // SAFETY: `packet_isa` chose the set because the processor has it.
        PacketIsa::Avx2 => unsafe { with_avx2(walk) },
        // SAFETY: as above.
        PacketIsa::Avx512 => unsafe { with_avx512(walk) },
    }
}

#[target_feature(enable = "avx2,fma")]
unsafe fn with_avx2<R>(walk: impl FnOnce() -> R) -> R {
    walk()
}

#[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512bw,avx512dq,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn with_avx512<R>(walk: impl FnOnce() -> R) -> R {
    walk()
}
