//! The peers compared in `benches/`; nothing of its own.
