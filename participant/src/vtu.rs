//! ParaView-readable output: unstructured-grid `.vtu` files and image-data
//! `.vti` files for fields on a box of cells (ASCII, every f64 written in its
//! shortest exact form, so a file reads back bit-identical), and a `.pvd`
//! collection that strings them into a time series.
//!
//! Every `.vtu` and `.vti` file is written to a temporary name and renamed,
//! so a run that stops at any moment leaves only complete files behind. The
//! `.pvd` is written so once; each later output extends it in place with one
//! write of its new line and the closing tags over the old closing tags
//! ([`Series`]): a process killed around that write leaves the old list or
//! the new one (a write of a few hundred bytes to a local file is not cut
//! short by a signal). Creating and renaming a file costs about 0.3 ms on
//! this project's virtual machines, which made a run with frequent outputs
//! (the pendulum's 200 in 10 s) spend more time on its `.pvd` files than
//! on its physics.

use crate::atomic::write_atomic;
use std::fmt::Write as _;
use std::fs::File;
use std::io;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// VTK cell types used by canopy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellKind {
    Vertex = 1,
    Line = 3,
    Triangle = 5,
}

impl CellKind {
    fn arity(self) -> usize {
        match self {
            CellKind::Vertex => 1,
            CellKind::Line => 2,
            CellKind::Triangle => 3,
        }
    }
}

/// One piece of unstructured grid: points (xyz interleaved), cells of one kind,
/// and named point data with 1 or 3 components.
pub struct Piece<'a> {
    pub points: &'a [f64],
    pub kind: CellKind,
    /// Point indices, `kind.arity()` per cell.
    pub connectivity: &'a [usize],
    pub point_data: Vec<(&'a str, usize, &'a [f64])>,
}

fn join(values: &[f64]) -> String {
    let mut s = String::with_capacity(values.len() * 20);
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{v}");
    }
    s
}

/// Write one `.vtu` file.
pub fn write_vtu(path: &Path, piece: &Piece) -> io::Result<()> {
    let n_points = piece.points.len() / 3;
    let arity = piece.kind.arity();
    let n_cells = piece.connectivity.len() / arity;
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    );
    s.push_str("<PointData>\n");
    for (name, comps, data) in &piece.point_data {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">{}</DataArray>",
            join(data)
        );
    }
    s.push_str("</PointData>\n<Points>\n");
    let _ = writeln!(
        s,
        "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">{}</DataArray>",
        join(piece.points)
    );
    s.push_str(
        "</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">",
    );
    let conn: Vec<String> = piece.connectivity.iter().map(|i| i.to_string()).collect();
    s.push_str(&conn.join(" "));
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    let offsets: Vec<String> = (1..=n_cells).map(|c| (c * arity).to_string()).collect();
    s.push_str(&offsets.join(" "));
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    let types: Vec<String> = (0..n_cells)
        .map(|_| (piece.kind as u8).to_string())
        .collect();
    s.push_str(&types.join(" "));
    s.push_str("</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    write_atomic(path, &s)
}

/// Fields on a box of cells: `cells` along x, y, z from `origin`,
/// `spacing` apart, each field one value or one 3-vector per cell (x
/// fastest). A graded box gives its cells' faces along each axis instead
/// (`faces`, world coordinates [m]): it is written as rectilinear grid
/// (`.vtr`).
pub struct Image<'a> {
    pub origin: [f64; 3],
    pub spacing: [f64; 3],
    pub cells: [usize; 3],
    pub faces: Option<&'a [Vec<f64>; 3]>,
    pub cell_data: Vec<(&'a str, usize, &'a [f64])>,
}

/// Write one `.vti` file.
pub fn write_vti(path: &Path, image: &Image) -> io::Result<()> {
    let [nx, ny, nz] = image.cells;
    let extent = format!("0 {nx} 0 {ny} 0 {nz}");
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
    let [o, h] = [image.origin, image.spacing].map(|v| join(&v));
    let _ = writeln!(
        s,
        "<ImageData WholeExtent=\"{extent}\" Origin=\"{o}\" Spacing=\"{h}\">\n<Piece Extent=\"{extent}\">\n<CellData>"
    );
    push_cell_data(&mut s, image);
    s.push_str("</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n");
    write_atomic(path, &s)
}

/// Write one `.vtr` file: a graded box's fields (`image.faces` given).
pub fn write_vtr(path: &Path, image: &Image) -> io::Result<()> {
    let [nx, ny, nz] = image.cells;
    let extent = format!("0 {nx} 0 {ny} 0 {nz}");
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"RectilinearGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
    let _ = writeln!(
        s,
        "<RectilinearGrid WholeExtent=\"{extent}\">\n<Piece Extent=\"{extent}\">\n<Coordinates>"
    );
    for (axis, faces) in ["x", "y", "z"]
        .iter()
        .zip(image.faces.into_iter().flatten())
    {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float64\" Name=\"{axis}\" format=\"ascii\">{}</DataArray>",
            join(faces)
        );
    }
    s.push_str("</Coordinates>\n<CellData>\n");
    push_cell_data(&mut s, image);
    s.push_str("</CellData>\n</Piece>\n</RectilinearGrid>\n</VTKFile>\n");
    write_atomic(path, &s)
}

fn push_cell_data(s: &mut String, image: &Image) {
    for (name, comps, data) in &image.cell_data {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">{}</DataArray>",
            join(data)
        );
    }
}

/// Read the cell field `name` of a `.vti` or `.vtr` written by
/// [`write_vti`] or [`write_vtr`] (for tests and tools).
pub fn read_cell_data(path: &Path, name: &str) -> io::Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)?;
    let tag = format!("Name=\"{name}\"");
    let bad = |m: &str| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{}: {m}", path.display()),
        )
    };
    let start = text
        .find(&tag)
        .ok_or_else(|| bad(&format!("no field {name}")))?;
    let open = start + text[start..].find('>').ok_or_else(|| bad("unclosed tag"))? + 1;
    let close = open
        + text[open..]
            .find('<')
            .ok_or_else(|| bad("unclosed array"))?;
    text[open..close]
        .split_whitespace()
        .map(|v| v.parse().map_err(|_| bad(&format!("bad number {v:?}"))))
        .collect()
}

/// The `.pvd` file's first lines.
const PVD_HEAD: &str =
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n<Collection>\n";
/// Its closing tags, which each new output's line goes before.
const PVD_TAIL: &str = "</Collection>\n</VTKFile>\n";

/// A `.pvd` time series in the run directory, with its `.vtu` files under `vtk/`.
pub struct Series {
    dir: PathBuf,
    name: String,
    entries: Vec<(f64, String)>,
    /// The `.pvd` once written whole, and where its closing tags begin.
    pvd: Option<(File, u64)>,
    /// Whether `vtk/` is known to exist.
    vtk_made: bool,
}

impl Series {
    pub fn new(run_dir: &Path, name: &str) -> Series {
        Series {
            dir: run_dir.to_path_buf(),
            name: name.to_string(),
            entries: Vec::new(),
            pvd: None,
            vtk_made: false,
        }
    }

    /// Write output number `index` at simulated `time` and update the `.pvd`.
    pub fn write(&mut self, index: u64, time: f64, piece: &Piece) -> io::Result<PathBuf> {
        self.add(index, time, "vtu", |path| write_vtu(path, piece))
    }

    /// The same for fields on a box of cells (a `.vti` file; `.vtr` for a
    /// graded box).
    pub fn write_image(&mut self, index: u64, time: f64, image: &Image) -> io::Result<PathBuf> {
        match image.faces {
            None => self.add(index, time, "vti", |path| write_vti(path, image)),
            Some(_) => self.add(index, time, "vtr", |path| write_vtr(path, image)),
        }
    }

    fn add(
        &mut self,
        index: u64,
        time: f64,
        extension: &str,
        write: impl FnOnce(&Path) -> io::Result<()>,
    ) -> io::Result<PathBuf> {
        if !self.vtk_made {
            let vtk = self.dir.join("vtk");
            std::fs::create_dir_all(&vtk).map_err(|e| {
                io::Error::new(e.kind(), format!("cannot create {}: {e}", vtk.display()))
            })?;
            self.vtk_made = true;
        }
        let rel = format!("vtk/{}_{index:06}.{extension}", self.name);
        let path = self.dir.join(&rel);
        write(&path)?;
        self.entries.push((time, rel));
        match self.pvd.take() {
            Some((file, at)) => self.extend_pvd(file, at)?,
            None => self.write_pvd()?,
        }
        Ok(path)
    }

    fn pvd_path(&self) -> PathBuf {
        self.dir.join(format!("{}.pvd", self.name))
    }

    /// The `.pvd` listing every output so far, written whole.
    fn write_pvd(&mut self) -> io::Result<()> {
        let mut s = String::from(PVD_HEAD);
        for (t, f) in &self.entries {
            s.push_str(&pvd_line(*t, f));
        }
        s.push_str(PVD_TAIL);
        let path = self.pvd_path();
        write_atomic(&path, &s)?;
        let file = File::options()
            .write(true)
            .open(&path)
            .map_err(|e| named(&path, e))?;
        self.pvd = Some((file, (s.len() - PVD_TAIL.len()) as u64));
        Ok(())
    }

    /// The last output's line and the closing tags, written over the old
    /// closing tags at `at` in one write.
    fn extend_pvd(&mut self, file: File, at: u64) -> io::Result<()> {
        let (t, f) = self.entries.last().expect("an output was just added");
        let line = pvd_line(*t, f);
        let bytes = format!("{line}{PVD_TAIL}");
        file.write_all_at(bytes.as_bytes(), at)
            .map_err(|e| named(&self.pvd_path(), e))?;
        self.pvd = Some((file, at + line.len() as u64));
        Ok(())
    }

    /// The outputs written so far, (time, file) each, for a run checkpoint.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// A restarted run: the outputs written before its checkpoint were
    /// `entries`; the `.pvd` lists them again (and no later one).
    pub fn resume(&mut self, entries: Vec<(f64, String)>) -> io::Result<()> {
        self.entries = entries;
        self.write_pvd()
    }
}

/// One output's line in the `.pvd`.
fn pvd_line(time: f64, file: &str) -> String {
    format!("<DataSet timestep=\"{time}\" part=\"0\" file=\"{file}\"/>\n")
}

/// An error that names the file it is about.
fn named(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
}

/// Read the points of a `.vtu` written by [`write_vtu`] (for tests and tools).
pub fn read_points(path: &Path) -> io::Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)?;
    let start = text
        .find("<Points>")
        .and_then(|p| text[p..].find("format=\"ascii\">").map(|q| p + q + 15))
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidData, "no <Points> array"))?;
    let end = start
        + text[start..]
            .find("</DataArray>")
            .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidData, "unterminated <Points>"))?;
    text[start..end]
        .split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_names_its_file_and_leaves_no_file_aside() {
        // The output's name is taken by a directory, so the rename fails,
        // as a write on a full disk would.
        let dir = std::env::temp_dir().join(format!("canopy-vtu-fail-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("vtk/canopy_000000.vtu")).unwrap();
        let piece = Piece {
            points: &[0.0; 3],
            kind: CellKind::Vertex,
            connectivity: &[0],
            point_data: vec![],
        };
        let e = Series::new(&dir, "canopy")
            .write(0, 0.0, &piece)
            .unwrap_err();
        assert!(e.to_string().contains("vtk/canopy_000000.vtu"), "{e}");
        let aside: Vec<_> = std::fs::read_dir(dir.join("vtk"))
            .unwrap()
            .flatten()
            .filter(|f| f.path().extension().is_some_and(|x| x == "tmp"))
            .collect();
        assert!(aside.is_empty(), "{aside:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn points_read_back_bit_identical() {
        let dir = std::env::temp_dir().join(format!("canopy-vtu-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let points = [
            0.1,
            -0.0,
            1e-310,
            1.0 / 3.0,
            f64::MAX,
            -2.5e-7,
            7.0,
            8.0,
            9.0,
        ];
        let mut series = Series::new(&dir, "t");
        let path = series
            .write(
                0,
                0.0,
                &Piece {
                    points: &points,
                    kind: CellKind::Triangle,
                    connectivity: &[0, 1, 2],
                    point_data: vec![],
                },
            )
            .unwrap();
        let back = read_points(&path).unwrap();
        assert!(back
            .iter()
            .zip(&points)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(std::fs::read_to_string(dir.join("t.pvd"))
            .unwrap()
            .contains("vtk/t_000000.vtu"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The `.pvd` extended in place reads as the list written whole, output
    /// after output, and a resumed series (a restart) lists only the
    /// outputs it is given and goes on extending from there.
    #[test]
    fn the_pvd_extended_in_place_is_the_whole_list() {
        let dir = std::env::temp_dir().join(format!("canopy-pvd-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let piece = Piece {
            points: &[0.0; 3],
            kind: CellKind::Vertex,
            connectivity: &[0],
            point_data: vec![],
        };
        let whole = |entries: &[(f64, String)]| {
            let lines: String = entries.iter().map(|(t, f)| pvd_line(*t, f)).collect();
            format!("{PVD_HEAD}{lines}{PVD_TAIL}")
        };
        let pvd = || std::fs::read_to_string(dir.join("s.pvd")).unwrap();
        let mut series = Series::new(&dir, "s");
        for i in 0..5 {
            series.write(i, 0.05 * i as f64, &piece).unwrap();
            assert_eq!(pvd(), whole(series.entries()), "after output {i}");
        }
        let kept = series.entries()[..2].to_vec();
        let mut resumed = Series::new(&dir, "s");
        resumed.resume(kept.clone()).unwrap();
        assert_eq!(pvd(), whole(&kept));
        resumed.write(2, 0.1, &piece).unwrap();
        assert_eq!(pvd(), whole(resumed.entries()));
        assert_eq!(resumed.entries().len(), 3);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
