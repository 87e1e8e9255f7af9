module Loop = Proved_loop
