//! Taubin λ|μ low-pass filtering and structured-grid tools (Alter).
