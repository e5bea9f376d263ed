//! brume: a physically based renderer for participating media.
