//! The real robots: UR5, Panda, LWR4, TX40.
