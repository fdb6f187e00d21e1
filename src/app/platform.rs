//! What differs between the browser and a native window: opening and saving files, the
//! page URL (share links), and a machine-readable status for end-to-end tests.

/// What a file is for, which decides who receives it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// An `interpolab-scene/1` JSON scene.
    Scene,
    /// A G-code program (`.nc`, `.ngc`, `.gcode`, `.tap`, `.txt`).
    GCode,
    /// A LinuxCNC tool table (`.tbl`).
    ToolTable,
    /// A CAMotics project (`.camotics`).
    Project,
}

impl FileKind {
    /// The kind a file name suggests: G-code extensions, else a scene.
    #[must_use]
    pub fn from_name(name: &str) -> Self {
        let lower = name.to_ascii_lowercase();
        if [".nc", ".ngc", ".gcode", ".tap", ".cnc", ".txt"].iter().any(|e| lower.ends_with(e)) {
            Self::GCode
        } else if lower.ends_with(".tbl") {
            Self::ToolTable
        } else if lower.ends_with(".camotics") {
            Self::Project
        } else {
            Self::Scene
        }
    }

    /// The most bytes the app reads of such a file, and what to call it in the refusal.
    #[must_use]
    pub fn size_cap(self) -> (u64, &'static str) {
        match self {
            Self::Scene => (crate::numerics::limits::MAX_SCENE_BYTES, "scene"),
            Self::GCode => (crate::numerics::limits::MAX_PROGRAM_BYTES, "G-code program"),
            Self::ToolTable => (crate::numerics::limits::MAX_TOOL_TABLE_BYTES, "tool table"),
            Self::Project => (crate::numerics::limits::MAX_TOOL_TABLE_BYTES, "CAMotics project"),
        }
    }

    /// The `accept` list of the file picker.
    #[must_use]
    pub fn accept(self) -> &'static str {
        match self {
            Self::Scene => ".json,application/json",
            Self::GCode => ".nc,.ngc,.gcode,.tap,.cnc,.txt,text/plain",
            Self::ToolTable => ".tbl,text/plain",
            Self::Project => ".camotics,application/json",
        }
    }
}

/// A file the user gave the app.
#[derive(Clone, Debug)]
pub struct Incoming {
    /// File name (for messages).
    pub name: String,
    /// Its text, or why it could not be read.
    pub text: Result<String, String>,
    /// What it is for.
    pub kind: FileKind,
}

#[cfg(target_arch = "wasm32")]
mod imp {
    use std::cell::RefCell;
    use std::rc::Rc;

    use eframe::egui;
    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::*;

    use super::{FileKind, Incoming};

    /// Id of the hidden `<input type="file">` in `web/index.html`.
    pub const FILE_INPUT_ID: &str = "scene-file";
    /// Id of the hidden status element in `web/index.html`.
    pub const STATUS_ID: &str = "app-status";

    pub struct Platform {
        inbox: Rc<RefCell<Vec<Incoming>>>,
        /// What the next file chosen in the picker is for.
        picking: Rc<std::cell::Cell<FileKind>>,
    }

    fn document() -> Option<web_sys::Document> {
        web_sys::window()?.document()
    }

    impl Platform {
        pub fn new(ctx: &egui::Context) -> Self {
            let inbox: Rc<RefCell<Vec<Incoming>>> = Rc::default();
            let picking = Rc::new(std::cell::Cell::new(FileKind::Scene));
            if let Some(input) = document()
                .and_then(|d| d.get_element_by_id(FILE_INPUT_ID))
                .and_then(|e| e.dyn_into::<web_sys::HtmlInputElement>().ok())
            {
                let inbox2 = inbox.clone();
                let ctx2 = ctx.clone();
                let input2 = input.clone();
                let picking2 = picking.clone();
                let on_change = Closure::<dyn FnMut(web_sys::Event)>::new(move |_e: web_sys::Event| {
                    let Some(file) = input2.files().and_then(|f| f.get(0)) else {
                        return;
                    };
                    let name = file.name();
                    // A G-code file, tool table or project is what its name says whichever
                    // button opened the picker (and so is one given to the input by a test
                    // driver); anything else is what the button asked for.
                    let kind = match FileKind::from_name(&name) {
                        FileKind::Scene => picking2.get(),
                        k => k,
                    };
                    let inbox3 = inbox2.clone();
                    let ctx3 = ctx2.clone();
                    let input3 = input2.clone();
                    let (cap, what) = kind.size_cap();
                    if file.size() > cap as f64 {
                        let text =
                            Err(crate::numerics::limits::TextError::TooLarge { cap_mib: cap >> 20, what }.to_string());
                        inbox2.borrow_mut().push(Incoming { name, text, kind });
                        input2.set_value("");
                        ctx2.request_repaint();
                        return;
                    }
                    wasm_bindgen_futures::spawn_local(async move {
                        let text = match wasm_bindgen_futures::JsFuture::from(file.text()).await {
                            Ok(v) => v.as_string().ok_or_else(|| "the file is not text".to_owned()),
                            Err(e) => Err(format!("{e:?}")),
                        };
                        inbox3.borrow_mut().push(Incoming { name, text, kind });
                        // Allow choosing the same file again.
                        input3.set_value("");
                        ctx3.request_repaint();
                    });
                });
                let _ = input.add_event_listener_with_callback("change", on_change.as_ref().unchecked_ref());
                on_change.forget();
            } else {
                log::warn!("no #{FILE_INPUT_ID} element: the file picker is unavailable");
            }
            Self { inbox, picking }
        }

        pub fn pick_file(&mut self, kind: FileKind) {
            self.picking.set(kind);
            if let Some(input) = document()
                .and_then(|d| d.get_element_by_id(FILE_INPUT_ID))
                .and_then(|e| e.dyn_into::<web_sys::HtmlInputElement>().ok())
            {
                input.set_accept(kind.accept());
                input.click();
            }
        }

        pub fn take_incoming(&mut self) -> Vec<Incoming> {
            std::mem::take(&mut *self.inbox.borrow_mut())
        }

        pub fn save_text(&mut self, name: &str, text: &str) -> Result<String, String> {
            let err = |e: JsValue| format!("{e:?}");
            let doc = document().ok_or("no document")?;
            let parts = js_sys::Array::of1(&JsValue::from_str(text));
            let opts = web_sys::BlobPropertyBag::new();
            opts.set_type(if name.ends_with(".json") { "application/json" } else { "text/plain" });
            let blob = web_sys::Blob::new_with_str_sequence_and_options(&parts, &opts).map_err(err)?;
            let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(err)?;
            let a: web_sys::HtmlAnchorElement =
                doc.create_element("a").map_err(err)?.dyn_into().map_err(|_| "no anchor")?;
            a.set_href(&url);
            a.set_download(name);
            a.click();
            let _ = web_sys::Url::revoke_object_url(&url);
            Ok(format!("downloaded {name}"))
        }

        pub fn fragment(&self) -> String {
            web_sys::window().and_then(|w| w.location().hash().ok()).unwrap_or_default()
        }

        /// The page address's query (`?…`), for automation options (`app::query_options`).
        pub fn query(&self) -> String {
            web_sys::window().and_then(|w| w.location().search().ok()).unwrap_or_default()
        }

        pub fn set_fragment(&mut self, fragment: &str) {
            if let Some(h) = web_sys::window().and_then(|w| w.history().ok()) {
                let _ = h.replace_state_with_url(&JsValue::NULL, "", Some(&format!("#{fragment}")));
            }
        }

        pub fn share_url(&self, fragment: &str) -> String {
            let loc = web_sys::window().map(|w| w.location());
            let base = loc
                .map(|l| format!("{}{}", l.origin().unwrap_or_default(), l.pathname().unwrap_or_default()))
                .unwrap_or_default();
            format!("{base}#{fragment}")
        }

        pub fn set_status(&mut self, json: &str) {
            if let Some(e) = document().and_then(|d| d.get_element_by_id(STATUS_ID)) {
                e.set_text_content(Some(json));
            }
        }

        pub fn now_ms() -> f64 {
            web_sys::window().and_then(|w| w.performance()).map_or(0.0, |p| p.now())
        }

        pub fn ui(&mut self, _ctx: &egui::Context) {}

        pub fn can_pick_files() -> bool {
            true
        }

        /// Reads files dropped on the canvas (asynchronously, as browsers require).
        pub fn accept_dropped(&mut self, ctx: &egui::Context) {
            for f in ctx.input(|i| i.raw.dropped_files.clone()) {
                let inbox = self.inbox.clone();
                let ctx = ctx.clone();
                wasm_bindgen_futures::spawn_local(async move {
                    let name = f.path().display().to_string();
                    let bytes = f.bytes_async().await;
                    let kind = FileKind::from_name(&name);
                    inbox.borrow_mut().push(super::decode(name, bytes, kind));
                    ctx.request_repaint();
                });
            }
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
mod imp {
    use eframe::egui;

    use super::{FileKind, Incoming};

    /// Native: a small window asking for a path replaces the browser's file dialogs.
    pub struct Platform {
        open_dialog: Option<(String, FileKind)>,
        inbox: Vec<Incoming>,
        started: web_time::Instant,
    }

    impl Platform {
        pub fn new(_ctx: &egui::Context) -> Self {
            Self { open_dialog: None, inbox: Vec::new(), started: web_time::Instant::now() }
        }

        pub fn pick_file(&mut self, kind: FileKind) {
            self.open_dialog = Some((String::new(), kind));
        }

        pub fn take_incoming(&mut self) -> Vec<Incoming> {
            std::mem::take(&mut self.inbox)
        }

        pub fn save_text(&mut self, name: &str, text: &str) -> Result<String, String> {
            std::fs::write(name, text).map_err(|e| format!("cannot write {name}: {e}"))?;
            let full = std::fs::canonicalize(name).map_or_else(|_| name.to_owned(), |p| p.display().to_string());
            Ok(format!("saved {full}"))
        }

        pub fn fragment(&self) -> String {
            String::new()
        }

        pub fn query(&self) -> String {
            String::new()
        }

        pub fn set_fragment(&mut self, _fragment: &str) {}

        pub fn share_url(&self, fragment: &str) -> String {
            format!("#{fragment}")
        }

        pub fn set_status(&mut self, _json: &str) {}

        pub fn now_ms() -> f64 {
            0.0
        }

        pub fn can_pick_files() -> bool {
            true
        }

        pub fn ui(&mut self, ctx: &egui::Context) {
            let Some((path, kind)) = self.open_dialog.as_mut() else {
                return;
            };
            let kind = *kind;
            let mut open = true;
            let mut load = false;
            let title = match kind {
                FileKind::Scene => "Open a scene file",
                FileKind::GCode => "Open a G-code program",
                FileKind::ToolTable => "Open a tool table",
                FileKind::Project => "Open a CAMotics project",
            };
            egui::Window::new(title).open(&mut open).collapsible(false).show(ctx, |ui| {
                ui.label("Path of the file:");
                let r = ui.text_edit_singleline(path);
                load = ui.button("Open").clicked() || (r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)));
            });
            if load {
                let p = path.clone();
                let (cap, what) = kind.size_cap();
                let text = std::fs::File::open(&p)
                    .map_err(|e| e.to_string())
                    .and_then(|f| crate::numerics::limits::read_text(f, cap, what))
                    .map_err(|e| format!("cannot read {p}: {e}"));
                self.inbox.push(Incoming { name: p, text, kind });
                self.open_dialog = None;
            } else if !open {
                self.open_dialog = None;
            }
            let _ = self.started;
        }

        /// Reads files dropped on the window.
        pub fn accept_dropped(&mut self, ctx: &egui::Context) {
            for f in ctx.input(|i| i.raw.dropped_files.clone()) {
                let name = f.path().display().to_string();
                let kind = FileKind::from_name(&name);
                self.inbox.push(super::decode(name, f.bytes(), kind));
            }
        }
    }
}

pub use imp::Platform;

fn decode(name: String, bytes: Result<Vec<u8>, String>, kind: FileKind) -> Incoming {
    let (cap, what) = kind.size_cap();
    let text = bytes.and_then(|b| {
        crate::numerics::limits::check_size(b.len(), cap, what).map_err(|e| e.to_string())?;
        crate::numerics::limits::text_from_bytes(b).map_err(|e| e.to_string())
    });
    Incoming { name, text, kind }
}
