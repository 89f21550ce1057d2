//! Tests of `guard`: steps undone, replays bitwise, snapshots.

use super::Guard;
use crate::body::Shape;
use crate::world::{BodySpec, Scene, Settings, World};

/// Eight boxes falling in a column onto a fixed box: contacts from step ~20.
fn column() -> World {
    let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let floor = BodySpec { shape: Some(Shape::cuboid([5.0, 5.0, 0.5]).unwrap()), fixed: true, ..Default::default() };
    scene.add_body(floor).unwrap();
    for k in 0..8 {
        let spec = BodySpec {
            shape: Some(Shape::cuboid([0.2, 0.2, 0.2]).unwrap()),
            density: Some(500.0),
            position: [0.03 * k as f64, 0.0, 1.0 + 0.5 * k as f64],
            ..Default::default()
        };
        scene.add_body(spec).unwrap();
    }
    scene.build(&Settings::new(1.0 / 60.0)).unwrap()
}

fn bits(w: &World) -> Vec<u64> {
    let b = &w.bodies;
    let rows = b.position.iter().chain(&b.linear_velocity).chain(&b.angular_velocity);
    rows.flatten().chain(b.orientation.iter().flatten()).map(|x| x.to_bits()).chain([w.steps]).collect()
}

#[test]
fn a_panic_inside_a_step_is_undone_exactly() {
    let (mut world, mut twin) = (column(), column());
    let mut guard = Guard::default();
    world.step_guarded(&mut guard, 30, &mut || false).unwrap();
    world.fail_at = Some(47);
    let err = world.step_guarded(&mut guard, 40, &mut || false).unwrap_err();
    assert!(err.message.contains("internal error in stage 'narrow_phase'"), "{}", err.message);
    assert!(err.message.contains("injected failure"), "{}", err.message);
    assert_eq!(world.steps, 47);
    twin.step(30).unwrap();
    twin.step(17).unwrap();
    assert_eq!(bits(&world), bits(&twin));
    world.fail_at = None;
    world.step_guarded(&mut guard, 20, &mut || false).unwrap();
    twin.step(20).unwrap();
    assert_eq!(bits(&world), bits(&twin));
}

#[test]
fn a_panic_while_preparing_is_undone_to_the_start_of_the_call() {
    let (mut world, mut twin) = (column(), column());
    let mut guard = Guard::default();
    world.step_guarded(&mut guard, 10, &mut || false).unwrap();
    world.step_guarded(&mut guard, 15, &mut || false).unwrap();
    // As a writable view does: the guard logs what is written through it.
    guard.expose(super::exposed::LINEAR_VELOCITY);
    world.bodies.linear_velocity[3] = [0.5, 0.0, 0.0];
    world.fail_at = Some(u64::MAX);
    let err = world.step_guarded(&mut guard, 5, &mut || false).unwrap_err();
    assert!(err.message.contains("internal error while preparing"), "{}", err.message);
    twin.step(10).unwrap();
    twin.step(15).unwrap();
    twin.bodies.linear_velocity[3] = [0.5, 0.0, 0.0];
    assert_eq!(bits(&world), bits(&twin));
    world.fail_at = None;
    world.step_guarded(&mut guard, 5, &mut || false).unwrap();
    twin.step(5).unwrap();
    assert_eq!(bits(&world), bits(&twin));
}

#[test]
fn an_interrupt_stops_at_a_step_boundary() {
    let mut world = column();
    let mut calls = 0;
    let done = world.step_guarded(&mut Guard::default(), 100, &mut || {
        calls += 1;
        calls == 5
    });
    assert_eq!(done.unwrap(), 5);
    assert_eq!(world.steps, 5);
}

#[test]
fn snapshot_bytes_round_trip_steps_on_bitwise() {
    let mut world = column();
    world.step(40).unwrap();
    let mut loaded = World::from_bytes(&world.to_bytes().unwrap()).unwrap();
    world.step(40).unwrap();
    loaded.step(40).unwrap();
    assert_eq!(bits(&world), bits(&loaded));
    let data = world.to_bytes().unwrap();
    for cut in [0, 10, 40, data.len() / 2, data.len() - 1] {
        assert!(World::from_bytes(&data[..cut]).is_err(), "cut at {cut}");
    }
}

#[test]
fn a_new_checkpoint_is_copied_into_the_last_ones_buffers_and_undoes_exactly() {
    // A fresh clone per checkpoint cost a million-body world 3.8 s of new
    // pages every 256 calls; copied into the last checkpoint's arrays, 0.75 s.
    let (mut world, mut twin) = (column(), column());
    let mut guard = Guard::default();
    world.step_guarded(&mut guard, 1, &mut || false).unwrap();
    let buffer = |g: &Guard| g.checkpoint.as_ref().map(|cp| cp.bodies.position.as_ptr());
    let first = buffer(&guard);
    for _ in 0..super::CHECKPOINT_CALLS + 3 {
        world.step_guarded(&mut guard, 1, &mut || false).unwrap();
    }
    assert_eq!(guard.calls.len(), 4, "a second checkpoint was taken {} calls ago", guard.calls.len());
    assert_eq!(buffer(&guard), first);
    assert_eq!(guard.checkpoint.as_ref().map(|cp| cp.steps), Some(super::CHECKPOINT_CALLS as u64));
    world.fail_at = Some(world.steps + 2);
    world.step_guarded(&mut guard, 5, &mut || false).unwrap_err();
    twin.step(super::CHECKPOINT_CALLS as u64 + 6).unwrap();
    assert_eq!(bits(&world), bits(&twin));
}

#[test]
fn a_restore_copies_into_the_viewed_arrays_and_is_bitwise() {
    // A restore cloned the snapshot afresh (a gigabyte of new pages for a
    // million bodies) before copying the viewed arrays back; it now copies
    // into this world's arrays, whose addresses NumPy's views hold.
    let (mut world, mut twin) = (column(), column());
    world.step(30).unwrap();
    let snap = world.clone();
    world.step(40).unwrap();
    let views = super::super::snapshot::view_arrays(&world);
    world.restore(&snap).unwrap();
    assert_eq!(super::super::snapshot::view_arrays(&world), views);
    world.step(40).unwrap();
    twin.step(70).unwrap();
    assert_eq!(bits(&world), bits(&twin));
}
