"""LightningDataModules of the three branches, thin wrappers over :mod:`sdn3d.data.datasets`."""

from datamodules._base import EmptyDataError
from datamodules.geometric import GeometricDataModule
from datamodules.semantic import SemanticDataModule
from datamodules.textural import TexturalDataModule

__all__ = ["SemanticDataModule", "GeometricDataModule", "TexturalDataModule", "EmptyDataError"]
