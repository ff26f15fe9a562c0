//! Quaternion mesh deformation (Samareh, NASA TM-2002-211646).
