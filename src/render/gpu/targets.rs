//! A view's off-screen targets: the (multisampled) colour and depth it is drawn into and the
//! resolved image the composite copies into egui's pass.

use eframe::egui_wgpu::wgpu;

/// Format of a view's colour targets.
pub(super) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Format of a view's depth target.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// Off-screen targets of one view at one size.
pub(super) struct Targets {
    /// Size (pixels).
    pub(super) size: [u32; 2],
    /// The multisampled colour (`None` at one sample).
    pub(super) msaa: Option<wgpu::TextureView>,
    /// Depth.
    pub(super) depth: wgpu::TextureView,
    /// The image (resolved colour).
    pub(super) resolved: wgpu::TextureView,
    /// The image bound for the composite.
    pub(super) composite: wgpu::BindGroup,
}

impl Targets {
    /// The targets of a view of `size` pixels at `sample_count` samples, its image bound for
    /// the composite through `composite_layout`.
    pub(super) fn new(
        device: &wgpu::Device,
        size: [u32; 2],
        sample_count: u32,
        composite_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let extent = wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 };
        let texture = |label: &str, format, samples, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let resolved = texture(
            "interpolab view image",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let msaa = (sample_count > 1).then(|| {
            texture("interpolab view MSAA colour", COLOR_FORMAT, sample_count, wgpu::TextureUsages::RENDER_ATTACHMENT)
        });
        let depth =
            texture("interpolab view depth", DEPTH_FORMAT, sample_count, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let composite = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("interpolab composite bind group"),
            layout: composite_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&resolved) }],
        });
        Self { size, msaa, depth, resolved, composite }
    }
}
