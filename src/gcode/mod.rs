//! G-code out (G01 chords, G02/G03 arcs, FANUC-style G06.2 NURBS) and in (parsing and
//! replaying programs against the design path).
