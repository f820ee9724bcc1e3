"""The design library: projects, designs and their immutable revisions with sign-offs."""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "projects",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("name", sa.String(100), nullable=False, unique=True),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("created_by", sa.String(100), nullable=False),
    )
    op.create_table(
        "designs",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("project_id", sa.Integer, sa.ForeignKey("projects.id"), nullable=False),
        sa.Column("name", sa.String(100), nullable=False),
        sa.Column("endpoint", sa.String(100), nullable=False),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("created_by", sa.String(100), nullable=False),
        sa.UniqueConstraint("project_id", "name", name="uq_designs_project_name"),
    )
    op.create_table(
        "revisions",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("design_id", sa.Integer, sa.ForeignKey("designs.id"), nullable=False),
        sa.Column("number", sa.Integer, nullable=False),
        sa.Column("parent", sa.Integer),
        sa.Column("request", sa.Text, nullable=False),
        sa.Column("content_hash", sa.String(64), nullable=False),
        sa.Column("author", sa.String(100), nullable=False),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("message", sa.Text, nullable=False),
        sa.Column("answer", sa.Text),
        sa.Column("passed", sa.Boolean),
        sa.Column("record_pdf", sa.LargeBinary),
        sa.Column("state", sa.String(16), nullable=False),
        sa.Column("checked_by", sa.String(100)),
        sa.Column("checked_at", sa.Float),
        sa.Column("approved_by", sa.String(100)),
        sa.Column("approved_at", sa.Float),
        sa.Column("superseded_by", sa.Integer),
        sa.UniqueConstraint("design_id", "number", name="uq_revisions_design_number"),
    )
    op.create_index("ix_revisions_content_hash", "revisions", ["content_hash"])
    op.create_index("ix_revisions_created_at", "revisions", ["created_at"])


def downgrade() -> None:
    op.drop_table("revisions")
    op.drop_table("designs")
    op.drop_table("projects")
