use glam::Vec3;

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Its centre.
    pub center: Vec3,
    /// Its radius (never negative).
    pub radius: f32,
}

impl Sphere {
    /// The sphere at `center` of `radius`.
    pub fn new(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
    }
}

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The least corner.
    pub min: Vec3,
    /// The greatest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box: the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box from `min` to `max`.
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The box around a sphere.
    pub fn of_sphere(s: &Sphere) -> Self {
        Self {
            min: s.center - Vec3::splat(s.radius),
            max: s.center + Vec3::splat(s.radius),
        }
    }

    /// Its centre.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Half its size along each axis.
    pub fn extents(&self) -> Vec3 {
        (self.max - self.min) * 0.5
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether it contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Whether `other` lies wholly inside it.
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && self.max.cmpge(other.max).all()
    }

    /// Its eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// Squared distance from `p` to the box (0 inside).
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        let d = (self.min - p).max(p - self.max).max(Vec3::ZERO);
        d.length_squared()
    }
}

/// Where a bound lies relative to a culling volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    /// Wholly outside the volume: not drawn.
    Outside,
    /// Partly inside: drawn, its children tested.
    Intersecting,
    /// Wholly inside: drawn, its children accepted untested.
    Inside,
}

impl Relation {
    /// Whether anything of it may be seen.
    pub fn visible(self) -> bool {
        self != Relation::Outside
    }

    /// The relation to the union of two volumes.
    pub fn union(self, other: Relation) -> Relation {
        use Relation::*;
        match (self, other) {
            (Inside, _) | (_, Inside) => Inside,
            (Outside, Outside) => Outside,
            _ => Intersecting,
        }
    }

    /// The relation to the intersection of two volumes (conservatively: Inside only if inside
    /// both).
    pub fn intersection(self, other: Relation) -> Relation {
        use Relation::*;
        match (self, other) {
            (Outside, _) | (_, Outside) => Outside,
            (Inside, Inside) => Inside,
            _ => Intersecting,
        }
    }
}
