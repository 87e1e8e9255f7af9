(* The generators live in lib/gen (conform --generated uses them too). *)
include Gen.Typed_gen
