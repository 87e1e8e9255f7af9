(* The generators live in lib/gen (conform --generated uses them too). *)
include Gen.Event_gen
