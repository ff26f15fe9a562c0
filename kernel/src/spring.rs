//! Spring-analogy mesh motion (Batina linear springs; Yang & Özgen angle-inclusion springs).
