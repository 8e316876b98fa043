"""What the tests share: builders of models and states, oracle mappings (Pinocchio, MuJoCo), fixtures."""
