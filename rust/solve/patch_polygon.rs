//! The polygon of a contact patch in its tangent plane: the convex hull of
//! its points, its area and centroid.

use super::limit_surface::{norm2, MAX_VERTICES};

/// Area and centroid of a convex polygon, counter-clockwise (no area, and the
/// centre of the segment between its farthest corners, when it has no area
/// to speak of).
pub(super) fn area_centroid(hull: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let mut extent: f64 = 0.0;
    for (k, a) in hull.iter().enumerate() {
        let b = hull[(k + 1) % hull.len()];
        let cross = a[0] * b[1] - a[1] * b[0];
        area += cross;
        cx += (a[0] + b[0]) * cross;
        cy += (a[1] + b[1]) * cross;
        extent = extent.max(norm2(a[0] - hull[0][0], a[1] - hull[0][1]));
    }
    if hull.len() >= 3 && area > 2e-6 * extent * extent {
        return (0.5 * area, [cx / (3.0 * area), cy / (3.0 * area)]);
    }
    let centre = match hull.len() {
        0 => [0.0; 2],
        1 => hull[0],
        _ => {
            let (a, b) = farthest_pair(hull);
            [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
        }
    };
    (0.0, centre)
}

/// `f` of the convex hull of points `p`, counter-clockwise (monotone chain),
/// in fixed arrays for a few points: it runs each time a patch's geometry is
/// refreshed. Many points (the face of a box on several triangles of a
/// mesh) are taken on the heap.
pub(super) fn with_hull<R>(p: &[[f64; 2]], f: impl FnOnce(&[[f64; 2]]) -> R) -> R {
    const N: usize = 2 * MAX_VERTICES;
    let sort = |pts: &mut [[f64; 2]]| pts.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    if p.len() > N {
        let mut pts = p.to_vec();
        sort(&mut pts);
        let mut hull = vec![[0.0; 2]; 2 * pts.len() + 1];
        let n = monotone_chain(&pts, &mut hull);
        return f(&hull[..n]);
    }
    let mut pts = [[0.0; 2]; N];
    pts[..p.len()].copy_from_slice(p);
    sort(&mut pts[..p.len()]);
    let mut hull = [[0.0; 2]; 2 * N + 1];
    let n = monotone_chain(&pts[..p.len()], &mut hull);
    f(&hull[..n])
}

/// The hull of sorted points `pts` into `hull` (room for 2·len + 1); returns
/// its number of corners. No tolerance on the turns: one relative to the
/// span drops true corners between points a round-off apart (the manifolds
/// of a face's triangles repeat them), and the patch's centre moves.
fn monotone_chain(pts: &[[f64; 2]], hull: &mut [[f64; 2]]) -> usize {
    let n = pts.len();
    if n <= 2 {
        hull[..n].copy_from_slice(pts);
        return if n == 2 && norm2(pts[0][0] - pts[1][0], pts[0][1] - pts[1][1]) <= 1e-12 { 1 } else { n };
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let chain = |q: [f64; 2], start: usize, hull: &mut [[f64; 2]], len: &mut usize| {
        while *len >= start + 2 && cross(hull[*len - 2], hull[*len - 1], q) <= 0.0 {
            *len -= 1;
        }
        hull[*len] = q;
        *len += 1;
    };
    let mut len = 0;
    for &q in pts {
        chain(q, 0, hull, &mut len);
    }
    len -= 1;
    let lower = len;
    for &q in pts.iter().rev() {
        chain(q, lower, hull, &mut len);
    }
    len - 1
}

/// The two corners of `c` furthest apart.
pub(super) fn farthest_pair(c: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut best = (c[0], c[0], 0.0);
    for a in c {
        for b in c {
            let d = norm2(a[0] - b[0], a[1] - b[1]);
            if d > best.2 {
                best = (*a, *b, d);
            }
        }
    }
    (best.0, best.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        norm2(a[0] - b[0], a[1] - b[1]) <= 1e-14
    }

    #[test]
    fn the_hull_of_many_points_keeps_the_corners_and_its_centroid() {
        // 40 points along the edges of a 2 x 1 rectangle off the origin, in
        // no order, repeats included (a face on several triangles): more than
        // the fixed arrays hold.
        let mut p = Vec::new();
        for k in 0..10 {
            let t = k as f64 / 10.0;
            p.extend([[1.0 + 2.0 * t, 0.5], [3.0, 0.5 + t], [3.0 - 2.0 * t, 1.5], [1.0, 1.5 - t]]);
        }
        p.reverse();
        p.push([2.0, 1.0]);
        let (area, c) = with_hull(&p, area_centroid);
        assert!((area - 2.0).abs() <= 1e-14, "{area}");
        assert!(close(c, [2.0, 1.0]), "{c:?}");
    }

    #[test]
    fn a_segment_and_a_point_have_no_area_and_their_middle() {
        let (area, c) = with_hull(&[[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]], area_centroid);
        assert_eq!(area, 0.0);
        assert!(close(c, [0.5, 0.5]), "{c:?}");
        assert_eq!(with_hull(&[[0.3, -0.2]; 3], area_centroid), (0.0, [0.3, -0.2]));
    }
}
