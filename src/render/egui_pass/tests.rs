use std::sync::Arc;

use eframe::egui::{
    self, Color32, Pos2, Rect, Shape, Stroke, StrokeKind, TextureId,
    epaint::{self, ClippedShape, Primitive, Tessellator},
    pos2, vec2,
};

use super::{AtlasGuard, FrameMeshes, RunDraw, egui_tessellator, eligible, replace_runs, runs};

fn clipped(clip: Rect, shape: Shape) -> ClippedShape {
    ClippedShape { clip_rect: clip, shape, transform_after_tessellation: epaint::emath::TSTransform::IDENTITY }
}

fn rect_shape(x: f32) -> Shape {
    Shape::rect_filled(Rect::from_min_size(pos2(x, 10.0), vec2(30.0, 20.0)), 2.0, Color32::from_rgb(40, 90, 160))
}

fn line(x: f32) -> Shape {
    Shape::line_segment([pos2(x, 0.0), pos2(x + 50.0, 40.0)], Stroke::new(1.5, Color32::LIGHT_GRAY))
}

/// A paint callback standing for a 3D view (its payload is only a marker).
fn callback() -> Shape {
    Shape::Callback(epaint::PaintCallback {
        rect: Rect::from_min_size(Pos2::ZERO, vec2(10.0, 10.0)),
        callback: Arc::new(7u8),
    })
}

/// A rectangle filled with another texture than the font atlas.
fn image(x: f32) -> Shape {
    let mut r = epaint::RectShape::filled(Rect::from_min_size(pos2(x, 0.0), vec2(20.0, 20.0)), 0.0, Color32::WHITE);
    r = r.with_texture(TextureId::User(3), Rect::from_min_max(Pos2::ZERO, pos2(1.0, 1.0)));
    Shape::Rect(r)
}

const A: Rect = Rect { min: Pos2 { x: 0.0, y: 0.0 }, max: Pos2 { x: 400.0, y: 300.0 } };
const B: Rect = Rect { min: Pos2 { x: 100.0, y: 0.0 }, max: Pos2 { x: 400.0, y: 300.0 } };

#[test]
fn runs_are_consecutive_atlas_shapes_in_one_clip_rectangle() {
    let shapes = vec![
        clipped(A, rect_shape(0.0)),
        clipped(A, line(10.0)),
        clipped(A, Shape::Noop),
        clipped(B, line(120.0)), // another clip rectangle: a new run
        clipped(B, callback()),  // a callback: in no run, and it ends the one before
        clipped(B, rect_shape(150.0)),
        clipped(B, image(160.0)), // another texture: in no run
        clipped(B, Shape::Vec(vec![line(170.0), rect_shape(180.0)])),
        clipped(B, Shape::Vec(vec![line(170.0), callback()])), // a Vec holding a callback: no
        clipped(A, line(0.0)),
    ];
    assert_eq!(runs(&shapes), vec![0..3, 3..4, 5..6, 7..8, 9..10]);
    assert!(!eligible(&shapes[4]) && !eligible(&shapes[6]) && !eligible(&shapes[8]));
    let mut moved = clipped(A, rect_shape(0.0));
    moved.transform_after_tessellation = epaint::emath::TSTransform::from_translation(vec2(1.0, 0.0));
    assert!(!eligible(&moved), "a shape transformed after tessellation stays egui's");
    assert_eq!(runs(&[]), Vec::<std::ops::Range<usize>>::new());
    assert_eq!(runs(&[clipped(A, callback())]), Vec::<std::ops::Range<usize>>::new());
}

fn plain_tessellator() -> Tessellator {
    Tessellator::new(1.0, epaint::TessellationOptions::default(), [1024, 64], vec![])
}

/// egui's own meshes for `shapes` (one per run, in order).
fn egui_meshes(shapes: &[ClippedShape]) -> Vec<(Rect, epaint::Mesh)> {
    plain_tessellator()
        .tessellate_shapes(shapes.to_vec())
        .into_iter()
        .filter_map(|p| match p.primitive {
            Primitive::Mesh(m) => Some((p.clip_rect, m)),
            Primitive::Callback(_) => None,
        })
        .collect()
}

#[test]
fn each_run_becomes_one_callback_in_its_place_drawing_egui_s_own_triangles() {
    let mut shapes = vec![
        clipped(A, rect_shape(0.0)),
        clipped(A, line(10.0)),
        clipped(A, callback()),
        clipped(B, line(120.0)),
        clipped(B, rect_shape(150.0)),
        clipped(B, image(160.0)),
    ];
    let expected = egui_meshes(&shapes);
    let mut frame = FrameMeshes::default();
    let mut made: Vec<(RunDraw, Rect)> = Vec::new();
    let mut make = |d: &RunDraw, clip: Rect| {
        made.push((d.clone(), clip));
        Shape::Callback(epaint::PaintCallback { rect: clip, callback: Arc::new(made.len()) })
    };
    let n = replace_runs(&mut shapes, &mut plain_tessellator(), &mut frame, 1 << 20, &mut make);
    assert_eq!(n, 2);
    // Order kept: run 1's callback, a Noop, the 3D view's callback, run 2's, a Noop, the image.
    let ordinal = |s: &Shape| match s {
        Shape::Callback(c) => c.callback.downcast_ref::<usize>().copied(),
        _ => None,
    };
    assert_eq!(ordinal(&shapes[0].shape), Some(1));
    assert!(matches!(shapes[1].shape, Shape::Noop));
    assert!(matches!(&shapes[2].shape, Shape::Callback(c) if c.callback.downcast_ref::<u8>() == Some(&7)));
    assert_eq!(ordinal(&shapes[3].shape), Some(2));
    assert!(matches!(shapes[4].shape, Shape::Noop));
    assert!(matches!(shapes[5].shape, Shape::Rect(_)), "the image stays egui's");
    assert_eq!(made.iter().map(|(_, c)| *c).collect::<Vec<_>>(), vec![A, B], "each run keeps its clip rectangle");
    // The frame's meshes are egui's meshes of the two runs (the image's mesh is egui's third).
    assert_eq!(expected.len(), 3);
    let mut next_index = 0u32;
    for ((draw, clip), (egui_clip, mesh)) in made.iter().zip(&expected) {
        assert_eq!(clip, egui_clip);
        assert_eq!(draw.indices.start, next_index, "runs follow one another in the index buffer");
        next_index = draw.indices.end;
        let ours: Vec<epaint::Vertex> = frame.indices[draw.indices.start as usize..draw.indices.end as usize]
            .iter()
            .map(|&i| frame.vertices[i as usize])
            .collect();
        let theirs: Vec<epaint::Vertex> = mesh.indices.iter().map(|&i| mesh.vertices[i as usize]).collect();
        assert_eq!(ours, theirs, "the same triangles, vertex for vertex");
    }
    assert_eq!(next_index as usize, frame.indices.len());
}

#[test]
fn past_the_vertex_cap_a_run_goes_to_egui_as_its_mesh() {
    let mut shapes = vec![clipped(A, rect_shape(0.0)), clipped(B, line(120.0)), clipped(A, rect_shape(200.0))];
    let expected = egui_meshes(&shapes);
    let first = expected[0].1.vertices.len();
    // Room for the first run only (and not for the second, however small).
    let mut frame = FrameMeshes::default();
    let mut make =
        |_: &RunDraw, clip: Rect| Shape::Callback(epaint::PaintCallback { rect: clip, callback: Arc::new(0usize) });
    let n = replace_runs(&mut shapes, &mut plain_tessellator(), &mut frame, first + 1, &mut make);
    assert_eq!(n, 1);
    assert_eq!(frame.vertices.len(), first);
    assert!(matches!(shapes[0].shape, Shape::Callback(_)));
    for (k, cs) in shapes.iter().enumerate().skip(1) {
        let Shape::Mesh(m) = &cs.shape else { panic!("run {k} should be egui's mesh") };
        assert_eq!(m.vertices, expected[k].1.vertices);
        assert_eq!(m.indices, expected[k].1.indices);
        assert_eq!(m.texture_id, TextureId::default());
    }
}

#[test]
fn the_tessellator_is_egui_s_own_text_discs_and_all() {
    let ctx = egui::Context::default();
    for ppp in [1.0f32, 1.5] {
        let input = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, vec2(640.0, 480.0))),
            ..Default::default()
        };
        ctx.set_pixels_per_point(ppp);
        let mut value = 0.4f64;
        let mut run = |ctx: &egui::Context| {
            ctx.run_ui(input.clone(), |ui| {
                ui.label("Feed 1 200 mm/min — tolérance 0,01 µm");
                ui.add(egui::Slider::new(&mut value, 0.0..=1.0).text("tolerance"));
                let _ = ui.button("Fit");
                ui.separator();
                let p = ui.painter();
                for r in [0.6f32, 1.0, 2.5, 4.0, 7.0] {
                    p.circle_filled(pos2(100.0 + 20.0 * r, 300.0), r, Color32::from_rgb(200, 120, 40));
                }
                p.rect_stroke(
                    Rect::from_min_size(pos2(300.0, 300.0), vec2(40.0, 30.0)),
                    3.0,
                    Stroke::new(1.0, Color32::GRAY),
                    StrokeKind::Inside,
                );
            })
        };
        // The first frame lays the glyphs out; the second is drawn with a settled atlas.
        run(&ctx).textures_delta.clear();
        let mut out = run(&ctx);
        out.textures_delta.clear();
        let theirs = ctx.tessellate(out.shapes.clone(), out.pixels_per_point);
        let ours = egui_tessellator(&ctx).tessellate_shapes(out.shapes);
        assert_eq!(theirs.len(), ours.len());
        let mut textured = 0;
        for (t, o) in theirs.iter().zip(&ours) {
            assert_eq!(t.clip_rect, o.clip_rect);
            let (Primitive::Mesh(t), Primitive::Mesh(o)) = (&t.primitive, &o.primitive) else {
                panic!("no callbacks here")
            };
            assert_eq!(t.vertices, o.vertices, "at {ppp} pixels per point");
            assert_eq!(t.indices, o.indices);
            textured += usize::from(t.vertices.iter().any(|v| v.uv != epaint::WHITE_UV));
        }
        assert!(textured > 0, "text and discs sample the atlas");
        // The small circles were drawn from the atlas's prepared discs (a quad each), not as
        // polygons: so the discs' places matter and were checked above.
        let disc_quads = theirs
            .iter()
            .filter_map(|p| match &p.primitive {
                Primitive::Mesh(m) => Some(m),
                Primitive::Callback(_) => None,
            })
            .flat_map(|m| m.vertices.iter())
            .filter(|v| v.color == Color32::from_rgb(200, 120, 40) && v.uv != epaint::WHITE_UV)
            .count();
        assert!(disc_quads >= 4 * 4, "{disc_quads} disc vertices");
    }
}

#[test]
fn only_the_same_atlas_grown_by_new_glyphs_is_used() {
    let options = epaint::text::TextOptions::default();
    let at = |fill_ratio: f32| AtlasGuard { fill_ratio, text_options: options };
    assert!(AtlasGuard::same_atlas(Some(at(0.1)), at(0.1)));
    assert!(AtlasGuard::same_atlas(Some(at(0.1)), at(0.2)), "glyphs added this frame: the same texture");
    assert!(!AtlasGuard::same_atlas(None, at(0.1)), "the first frame: nothing known");
    assert!(!AtlasGuard::same_atlas(Some(at(0.5)), at(0.1)), "emptier: the atlas was cleared");
    assert!(!AtlasGuard::same_atlas(Some(at(0.79)), at(0.8)), "about to be cleared");
    let other = epaint::text::TextOptions { font_hinting: !options.font_hinting, ..options };
    assert!(!AtlasGuard::same_atlas(Some(at(0.1)), AtlasGuard { fill_ratio: 0.1, text_options: other }));
}
