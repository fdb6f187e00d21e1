//! Tool tables: every field and unit, the remark convention, round trips, CAMotics projects
//! and specs against closed forms (`tests/reference/cycles.rs` checks the length offsets
//! against `rs274 -t`).

use glam::DVec3;

use super::*;
use crate::geom::CutterKind;

const TABLE: &str = "\
; a LinuxCNC tool table
T1 P1 Z12.5 D6 ;ball 6mm roughing
T2  P2\tX1 Y-2 Z30.25 D10 I10 J-5 Q3 ;Bull r=0.5 finishing
t7 p3 z-4 d-3.175 ;drill
T8 P4 Z1 A10 B20 C30 U1 V2 W3 D2 ;v90 engraver
T9 P5 Z2 D4 ;  VBIT 60
T10 Z3 D8 ;drill 135 long
T11 P6 Z0.125 D0.25 ;my favourite cutter
T12 P7 Z4 D3

";

#[test]
fn a_tbl_is_read_word_by_word_in_the_machines_units() {
    let t = ToolTable::from_linuxcnc(TABLE, TableUnits::Mm).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(t.len(), 8);
    let one = t.get(1).cloned().unwrap_or_default();
    assert_eq!(
        (one.pocket, one.offset_mm, one.diameter_mm, one.shape),
        (Some(1), DVec3::new(0.0, 0.0, 12.5), 6.0, ToolShape::Ball)
    );
    assert_eq!(one.comment, "ball 6mm roughing");
    assert!(!one.shape_assumed);
    let two = t.get(2).cloned().unwrap_or_default();
    assert_eq!(two.offset_mm, DVec3::new(1.0, -2.0, 30.25));
    assert_eq!(two.shape, ToolShape::Bull { corner_radius_mm: 0.5 });
    assert_eq!(two.lathe, Some(LatheTool { front_angle_deg: 10.0, back_angle_deg: -5.0, orientation: 3 }));
    let seven = t.get(7).cloned().unwrap_or_default();
    assert_eq!(
        (seven.diameter_mm, seven.shape),
        (3.175, ToolShape::Drill { point_angle_deg: DEFAULT_DRILL_POINT_DEG })
    );
    let eight = t.get(8).cloned().unwrap_or_default();
    assert_eq!(
        (eight.rotary_offset_deg, eight.uvw_offset_mm),
        (DVec3::new(10.0, 20.0, 30.0), DVec3::new(1.0, 2.0, 3.0))
    );
    assert_eq!(eight.shape, ToolShape::V { tip_angle_deg: 90.0 });
    assert_eq!(t.get(9).map(|t| t.shape), Some(ToolShape::V { tip_angle_deg: 60.0 }));
    assert_eq!(t.get(10).map(|t| (t.pocket, t.shape)), Some((None, ToolShape::Drill { point_angle_deg: 135.0 })));
    for n in [11, 12] {
        let e = t.get(n).cloned().unwrap_or_default();
        assert!(
            e.shape == ToolShape::Flat && e.shape_assumed,
            "tool {n}: a remark without a shape word is a flat end mill, assumed"
        );
    }
    // In inches every length scales by 25.4, the angles do not.
    let i = ToolTable::from_linuxcnc(TABLE, TableUnits::Inch).unwrap_or_else(|e| panic!("{e}"));
    for (a, b) in t.iter().zip(i.iter()) {
        assert_eq!(a.offset_mm * 25.4, b.offset_mm);
        assert_eq!(a.uvw_offset_mm * 25.4, b.uvw_offset_mm);
        assert_eq!(a.rotary_offset_deg, b.rotary_offset_deg);
        assert_eq!(a.diameter_mm * 25.4, b.diameter_mm);
        assert_eq!(a.corner_radius_mm().map(|r| r * 25.4), b.corner_radius_mm());
    }
}

#[test]
fn a_written_table_reads_back_the_same() {
    for units in [TableUnits::Mm, TableUnits::Inch] {
        let t = ToolTable::from_linuxcnc(TABLE, units).unwrap_or_else(|e| panic!("{e}"));
        let text = t.to_linuxcnc(units);
        let back = ToolTable::from_linuxcnc(&text, units).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(back, t, "{text}");
    }
    // A table from specs: the shapes are written into the remarks.
    let mut t = ToolTable::new();
    for spec in ["1:ball:6", "2:bull:10:1", "3:v:6:90", "4:flat:3", "5:drill:8:135"] {
        t.insert(parse_tool_spec(spec).unwrap_or_else(|e| panic!("{e}")), spec).unwrap_or_else(|e| panic!("{e}"));
    }
    let back =
        ToolTable::from_linuxcnc(&t.to_linuxcnc(TableUnits::Mm), TableUnits::Mm).unwrap_or_else(|e| panic!("{e}"));
    for (a, b) in t.iter().zip(back.iter()) {
        assert_eq!((a.number, a.shape, a.diameter_mm, b.shape_assumed), (b.number, b.shape, b.diameter_mm, false));
    }
}

#[test]
fn bad_tbl_lines_are_refused_naming_the_line() {
    for (text, want) in [
        ("T1 P1 Z1\nT2 P2 Z1 K3\n", "line 2: 'K3'"),
        ("T1 P1 Z1 Z2\n", "line 1: Z appears twice"),
        ("P1 Z1 D3 ;ball\n", "line 1: no tool number"),
        ("T1 P1\nT1 P2\n", "line 2: tool 1 is already defined (line 1)"),
        ("T1 P1 Zabc\n", "'Zabc'"),
        ("T-3 P1\n", "from 0"),
        ("T1 D6 ;bull finishing\n", "corner radius"),
        ("T1 D6 ;bull r=3\n", "half the diameter"),
        ("T1 D6 ;v engraver\n", "tip angle"),
        ("T1 D6 ;v200\n", "between 0 and 180"),
    ] {
        let e = ToolTable::from_linuxcnc(text, TableUnits::Mm).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(want), "{text:?}: {e:?} lacks {want:?}");
    }
    let big = "T1 P1\n".to_owned() + &" ".repeat(usize::try_from(MAX_TOOL_TABLE_BYTES).unwrap_or(usize::MAX));
    assert!(matches!(ToolTable::from_linuxcnc(&big, TableUnits::Mm), Err(ToolError::TooLarge { .. })));
    let many: String = (0..=MAX_TOOLS).map(|n| format!("T{n}\n")).collect();
    assert!(matches!(ToolTable::from_linuxcnc(&many, TableUnits::Mm), Err(ToolError::TooMany { .. })));
}

#[test]
fn specs_give_the_shapes_and_the_cutters() {
    let ball = parse_tool_spec("1:ball:6").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        (ball.number, ball.shape, ball.diameter_mm, ball.corner_radius_mm()),
        (1, ToolShape::Ball, 6.0, Some(3.0))
    );
    let c = ball.cutter().and_then(Result::ok).map(|c| (c.kind(), c.radius_mm, c.corner_radius_mm));
    assert_eq!(c, Some((CutterKind::Ball, 3.0, 3.0)));
    let bull = parse_tool_spec("2:bull:10:1").unwrap_or_else(|e| panic!("{e}"));
    let c = bull.cutter().and_then(Result::ok).map(|c| (c.kind(), c.radius_mm, c.corner_radius_mm));
    assert_eq!(c, Some((CutterKind::Fillet, 5.0, 1.0)));
    assert_eq!(
        parse_tool_spec("4:flat:3").ok().and_then(|t| t.cutter()).and_then(Result::ok).map(|c| c.kind()),
        Some(CutterKind::Flat)
    );
    let v = parse_tool_spec("3:v:6:90").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((v.shape, v.cutter().is_none()), (ToolShape::V { tip_angle_deg: 90.0 }, true));
    assert_eq!(parse_tool_spec("5:drill:8").map(|t| t.shape), Ok(ToolShape::Drill { point_angle_deg: 118.0 }));
    for (spec, want) in [
        ("1:ball", "N:shape:diameter"),
        ("x:ball:6", "not a tool number"),
        ("1:ball:0", "above 0"),
        ("1:bull:6", "write 1:bull:6:1"),
        ("1:bull:6:3", "half the diameter"),
        ("1:v:6", "write 1:v:6:90"),
        ("1:cone:6", "not a shape"),
        ("1:ball:6:2", "no fourth field"),
    ] {
        let e = parse_tool_spec(spec).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(want) && e.contains(spec), "{spec}: {e:?} lacks {want:?}");
    }
}

const PROJECT: &str = r#"{
  "units": "imperial",
  "resolution-mode": "medium",
  "resolution": 0.5,
  "tools": {
    "1": {"units": "metric", "shape": "conical", "length": 2, "diameter": 2, "description": "engraver"},
    "2": {"units": "imperial", "shape": "ballnose", "length": 1, "diameter": 0.125, "description": ""},
    "3": {"shape": "Cylindrical", "diameter": 6},
    "4": {"units": "imperial", "shape": "snubnose", "length": 0.5, "diameter": 0.25, "snub_diameter": 0.0625},
    "5": {"shape": "spheroid"},
    "6": {}
  },
  "workpiece": {"automatic": false, "margin": 5, "bounds": {"min": [-32, -2, -12.7], "max": [32, 110, 0]}},
  "files": ["part.nc", "text.tpl"]
}"#;

#[test]
fn a_camotics_project_gives_its_tools_workpiece_and_files() {
    let p = ToolTable::from_camotics(PROJECT).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p.units, TableUnits::Inch);
    assert_eq!(p.files, vec!["part.nc".to_owned(), "text.tpl".to_owned()]);
    assert_eq!(
        p.workpiece,
        Some(CamoticsWorkpiece {
            automatic: false,
            margin_percent: 5.0,
            bounds_mm: Some((DVec3::new(-32.0, -2.0, -12.7), DVec3::new(32.0, 110.0, 0.0)))
        })
    );
    let t = &p.tools;
    assert_eq!(t.len(), 6);
    // Conical: R = 1, length 2 → included angle 2·atan(1/2) = 53.130…°.
    let ToolShape::V { tip_angle_deg } = t.get(1).map_or(ToolShape::Unknown, |t| t.shape) else {
        panic!("conical is a V")
    };
    assert!(
        (tip_angle_deg - 2.0 * 0.5f64.atan().to_degrees()).abs() < 1e-12 && (tip_angle_deg - 53.130_102).abs() < 1e-6
    );
    let two = t.get(2).cloned().unwrap_or_default();
    assert_eq!((two.shape, two.diameter_mm, two.length_mm), (ToolShape::Ball, 3.175, Some(25.4)));
    // No units: metric; no length: CAMotics' 10 mm.
    let three = t.get(3).cloned().unwrap_or_default();
    assert_eq!((three.shape, three.diameter_mm, three.length_mm), (ToolShape::Flat, 6.0, Some(10.0)));
    assert_eq!(t.get(4).map(|t| (t.shape, t.diameter_mm)), Some((ToolShape::Snub { tip_diameter_mm: 1.5875 }, 6.35)));
    assert_eq!(t.get(5).map(|t| t.shape), Some(ToolShape::Unknown));
    assert_eq!(t.get(6).map(|t| (t.shape, t.diameter_mm, t.length_mm)), Some((ToolShape::Flat, 2.0, Some(10.0))));
    for (text, want) in [
        ("[1, 2]", "project"),
        ("{\"tools\": {\"1\": {\"shape\": \"blade\"}}}", "tools.1.shape: 'blade' is not a CAMotics shape"),
        ("{\"tools\": {\"x\": {}}}", "tools.x"),
        ("{\"tools\": {\"1\": {\"diameter\": \"six\"}}}", "tools.1.diameter"),
        ("{\"units\": \"furlongs\"}", "units: must be"),
        ("{\"workpiece\": {\"bounds\": {\"min\": [0, 0], \"max\": [1, 1, 1]}}}", "workpiece.bounds.min"),
        ("<camotics/>", "not JSON"),
    ] {
        let e = ToolTable::from_camotics(text).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(want), "{text}: {e:?} lacks {want:?}");
    }
}

/// A spec written from a tool reads back to its shape and diameter; a cutter set over a
/// table keeps the table's offsets of that number (G43 still lifts it as the table says).
#[test]
fn a_tool_writes_its_spec_and_a_cutter_set_over_it_keeps_its_offsets() {
    let t = ToolTable::from_linuxcnc(TABLE, TableUnits::Mm).unwrap_or_else(|e| panic!("{e}"));
    let mut named = 0;
    for e in t.iter() {
        match e.spec() {
            Some(s) => {
                let back = parse_tool_spec(&s).unwrap_or_else(|err| panic!("{s}: {err}"));
                assert_eq!((back.number, back.shape, back.diameter_mm), (e.number, e.shape, e.diameter_mm), "{s}");
                named += 1;
            }
            None => assert!(matches!(e.shape, ToolShape::Snub { .. } | ToolShape::Unknown) || e.diameter_mm == 0.0),
        }
    }
    assert_eq!(named, t.len(), "every tool of this table has a shape a spec names");
    let mut t2 = t.clone();
    t2.set_cutter(parse_tool_spec("2:ball:4").unwrap_or_else(|e| panic!("{e}"))).unwrap_or_else(|e| panic!("{e}"));
    let (old, new) = (t.get(2).unwrap_or_else(|| panic!("T2")), t2.get(2).unwrap_or_else(|| panic!("T2")));
    assert_eq!((new.shape, new.diameter_mm), (ToolShape::Ball, 4.0));
    assert_eq!((new.offset_mm, new.pocket, new.uvw_offset_mm), (old.offset_mm, old.pocket, old.uvw_offset_mm));
    assert_eq!(new.offset_mm, DVec3::new(1.0, -2.0, 30.25));
    // A number the table lacks is added as the spec gives it.
    t2.set_cutter(parse_tool_spec("40:v:6:60").unwrap_or_else(|e| panic!("{e}"))).unwrap_or_else(|e| panic!("{e}"));
    let v = t2.get(40).unwrap_or_else(|| panic!("T40"));
    assert_eq!((v.shape, v.offset_mm), (ToolShape::V { tip_angle_deg: 60.0 }, DVec3::ZERO));
}
