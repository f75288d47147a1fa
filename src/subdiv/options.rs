//! What the subdivision surface is, besides the control mesh: sharp features and the rules
//! OpenSubdiv lets a user choose (`Sdc::Options`).

/// How boundary vertices are interpolated (`Sdc::Options::VtxBoundaryInterpolation`).
///
/// surfkit defaults to [`EdgesAndCorners`](Self::EdgesAndCorners), not OpenSubdiv's own
/// default [`None`](Self::None): with `None` OpenSubdiv builds no limit surface for faces
/// on the boundary (they get no patches), which surprises everyone who evaluates the limit.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum BoundaryInterpolation {
    /// No boundary rule: boundary faces have no limit surface (OpenSubdiv's default).
    None,
    /// Boundary edges are infinitely sharp creases; a boundary vertex on one face (a corner
    /// of valence 2) is smoothed like any crease vertex, as CGAL's Catmull–Clark does.
    EdgesOnly,
    /// Boundary edges are infinitely sharp and corners (boundary vertices of one face) are
    /// infinitely sharp too: the surface interpolates them.
    #[default]
    EdgesAndCorners,
}

impl BoundaryInterpolation {
    pub(crate) fn sdc(self) -> i32 {
        match self {
            Self::None => 0,
            Self::EdgesOnly => 1,
            Self::EdgesAndCorners => 2,
        }
    }
}

/// How face-varying data (UVs) is interpolated (`Sdc::Options::FVarLinearInterpolation`).
/// The default is OpenSubdiv's: [`All`](Self::All), bilinear UVs everywhere.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FaceVaryingInterpolation {
    /// Smooth everywhere, boundaries and corners included.
    None,
    /// Smooth except that UV corners (one face on a UV-boundary vertex) stay sharp.
    CornersOnly,
    /// As `CornersOnly`, plus sharpening of junctions of 3 or more UV regions.
    CornersPlus1,
    /// As `CornersPlus1`, plus sharpening of darts and concave corners.
    CornersPlus2,
    /// Linear along UV boundaries, smooth inside.
    Boundaries,
    /// Linear everywhere (bilinear UVs).
    #[default]
    All,
}

impl FaceVaryingInterpolation {
    pub(crate) fn sdc(self) -> i32 {
        match self {
            Self::None => 0,
            Self::CornersOnly => 1,
            Self::CornersPlus1 => 2,
            Self::CornersPlus2 => 3,
            Self::Boundaries => 4,
            Self::All => 5,
        }
    }
}

/// How semi-sharp creases lose sharpness per level (`Sdc::Options::CreasingMethod`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum CreasingMethod {
    /// Sharpness drops by 1 per level (RenderMan's classic rule).
    #[default]
    Uniform,
    /// Chaikin's rule: sharpness is averaged along a crease.
    Chaikin,
}

/// How triangles are refined (`Sdc::Options::TriangleSubdivision`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum TriangleSubdivision {
    /// Catmull–Clark's rules as for any polygon (what CGAL does).
    #[default]
    CatmullClark,
    /// Smooth triangle weights (Stam & Loop's modification) on all-triangle neighbourhoods.
    Smooth,
}

/// A sharp or semi-sharp crease on an edge of the control mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crease {
    /// The edge's two vertices (any order).
    pub vertices: [u32; 2],
    /// 0 smooth, `k` sharp for `k` levels then smooth, ≥ 10 infinitely sharp. OpenSubdiv
    /// stores sharpness as `f32`.
    pub sharpness: f32,
}

/// A sharp or semi-sharp corner vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    pub vertex: u32,
    /// As [`Crease::sharpness`].
    pub sharpness: f32,
}

/// Options of every subdivision entry function: the sharp features of the control mesh and
/// the rules to use. `Default` is a smooth surface with edges-and-corners boundaries.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SubdivOptions {
    pub creases: Vec<Crease>,
    pub corners: Vec<Corner>,
    pub boundary: BoundaryInterpolation,
    pub face_varying: FaceVaryingInterpolation,
    pub creasing: CreasingMethod,
    pub triangles: TriangleSubdivision,
}
