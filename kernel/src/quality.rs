//! Mesh quality: signed cell measures, inverted and folded cells, area ratios, wall angles.
