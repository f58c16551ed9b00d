//! The frame of angular rates, shared by the splines, the batch kernels and integration (a
//! ground-floor type: it imports nothing of ours).

/// The frame of angular rates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// ω = 2 q' q* (vector part), in world coordinates.
    World,
    /// ω_b = 2 q* q', in body coordinates.
    Body,
}
