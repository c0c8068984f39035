use super::*;

/// Arrays put borrowed are written exactly as the same arrays put owned, in one name order.
#[test]
fn borrowed_and_owned_arrays_encode_the_same() {
    let x = vec![1.5, -0.0, f64::MIN_POSITIVE, 3e300];
    let m = vec![3i32, -7];
    let id = vec![1i64 << 40, 2];
    let r = vec![9u32, 0, 4];
    let mut own = Blob::default();
    own.put("b.x", Item::F64(x.clone()));
    own.put("d.m", Item::I32(m.clone()));
    own.put("a.id", Item::I64(id.clone()));
    own.put("c.r", Item::U32(r.clone()));
    own.put("c.n", Item::U64(vec![5]));
    own.put_text("e.t", "text");
    let mut mixed = Blob::default();
    mixed.put_ref("b.x", Ref::F64(&x));
    mixed.put_ref("d.m", Ref::I32(&m));
    mixed.put_ref("a.id", Ref::I64(&id));
    mixed.put_ref("c.r", Ref::U32(&r));
    mixed.put("c.n", Item::U64(vec![5]));
    mixed.put_text("e.t", "text");
    let bytes = own.encode();
    assert_eq!(mixed.encode(), bytes);
    let back = Blob::decode(&bytes).unwrap();
    assert_eq!(back, own);
    assert_eq!(mixed.f64("b.x").unwrap(), x);
    // a name put again replaces the earlier array, borrowed or owned
    mixed.put("b.x", Item::F64(vec![2.0]));
    own.put("b.x", Item::F64(vec![2.0]));
    assert_eq!(mixed.encode(), own.encode());
}
