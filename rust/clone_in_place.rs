//! `Clone` for the large state structs, with a `clone_from` that reuses the
//! target's buffers field by field.
//!
//! A derived `Clone` keeps the default `clone_from` (`*self = source.clone()`):
//! every array is allocated afresh and the old ones freed. The step guard
//! copies the world into its checkpoint every 256 `step` calls; for a million
//! bodies that is a gigabyte, and fresh pages cost more than the copy (the
//! kernel zeroes each one on its first touch): 3.8 s a checkpoint, 12 % of a
//! loop of `step(1)` calls. Copied into the buffers of the last checkpoint,
//! the same copy takes a memcpy's time.
//!
//! `clone_in_place!(Type { field, ... })` implements both methods from the
//! list of fields; `clone` builds the struct literally, so a field left out of
//! the list does not compile.

macro_rules! clone_in_place {
    ($ty:ident { $($(#[$cfg:meta])* $field:ident),* $(,)? }) => {
        impl Clone for $ty {
            fn clone(&self) -> Self {
                $ty { $($(#[$cfg])* $field: self.$field.clone()),* }
            }

            fn clone_from(&mut self, source: &Self) {
                $($(#[$cfg])* self.$field.clone_from(&source.$field);)*
            }
        }
    };
}
