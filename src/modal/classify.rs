//! Wheel mode classification (see below).
