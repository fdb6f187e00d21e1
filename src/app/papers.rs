//! The papers the tabs are built from, one line each for the shown tab's help: authors,
//! English title, venue and year as our copies print them (where a copy leaves one out, the
//! line says so rather than guess). `docs/papers.md` cites each in full, with its original
//! title, what the product takes from it and where it departs.

/// The crease interpolation tab's paper.
pub const CREASE: &str = "Zhou Yanhong, Zhou Yunfei, Zhou Ji, Zhou Zude: “Tool-path direct interpolation for surfaces intersection machining in CNC system”, journal article, Huazhong University of Science and Technology, 1994 (the journal's name is not printed in our copy).";

/// The 5-axis steps tab's paper.
pub const FIVE_AXIS: &str = "Ji Junfeng, Zhou Laishui, An Luling, Zhang Chen: “A new determination method of tool step for 5-axis NC machining”, Journal of Chongqing University, 2010, no. 4, pp. 37–42.";

/// The chords tab's source.
pub const CHORDS: &str = "“Node calculation of equal-error straight lines approximating non-circular curves, and tool-path simulation”, web article (CNC technology » tool technology), 2019; no author is printed.";

/// The NURBS & G-code tab's paper.
pub const NURBS: &str = "Zhao Xiaoyun, Huo Yaguang, Song Xuding (Chang'an University, Taizhou University): NURBS direct interpolation in CNC systems and its machining test; title, venue and year are not printed in our copy.";

/// The fillet end mill and cutting simulation tabs' source.
pub const FIVE_AXIS_FINISHING: &str = "“Research on tool-path generation for five-axis NC machining of sculptured surfaces”, doctoral dissertation, Huazhong University of Science and Technology; author and year are not printed in our copy.";
