"""The store's tables, as SQLAlchemy Core tables: the migrations create them, the data layer reads and writes them.

Times are seconds since the epoch (floats), so both engines compare and order them the same way; JSON documents
are stored as text, exactly as written, so a revision's content hash stays checkable byte for byte.
"""

from __future__ import annotations

from sqlalchemy import (
    Boolean,
    Column,
    Float,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    MetaData,
    String,
    Table,
    Text,
    UniqueConstraint,
    text,
)

metadata = MetaData()

studies = Table(
    "studies", metadata,
    Column("id", String(32), primary_key=True),
    Column("spec", Text, nullable=False),
    Column("total", Integer, nullable=False),
    Column("state", String(16), nullable=False),
    Column("created_at", Float, nullable=False),
    Column("run_started_at", Float),
    Column("run_start_done", Integer, nullable=False, server_default="0"),
    Column("elapsed_s", Float, nullable=False, server_default="0"),
    Column("message", Text),
    # The process running the study and until when its claim holds; it renews the claim while it runs.
    Column("lease_owner", String(200)),
    Column("lease_expires", Float),
    Index("ix_studies_created_at", "created_at"),
)

study_rows = Table(
    "study_rows", metadata,
    Column("study_id", String(32), ForeignKey("studies.id"), primary_key=True),
    Column("idx", Integer, primary_key=True, autoincrement=False),
    Column("params", Text, nullable=False),
    Column("metrics", Text),
    Column("feasible", Boolean),
    Column("problem_type", String(100)),
    Column("detail", Text),
)

users = Table(
    "users", metadata,
    Column("id", Integer, primary_key=True),
    Column("name", String(100), nullable=False, unique=True),
    Column("password_hash", String(500)),
    # Space-separated role names (viewer, engineer, admin, checker, approver).
    Column("roles", String(500), nullable=False, server_default=""),
    Column("created_at", Float, nullable=False),
    # Raised when a password is reset or a role removed: sessions and tokens of an older epoch end at once.
    Column("credential_epoch", Integer, nullable=False, server_default="0"),
)

api_tokens = Table(
    "api_tokens", metadata,
    Column("id", Integer, primary_key=True),
    Column("token_hash", String(128), nullable=False, unique=True),
    Column("user_id", Integer, ForeignKey("users.id", ondelete="CASCADE"), nullable=False),
    Column("label", String(200)),
    Column("created_at", Float, nullable=False),
    Column("last_used_at", Float),
    # The user's credential epoch when the token was made: a token of an older epoch is refused.
    Column("epoch", Integer, nullable=False, server_default="0"),
    # After this the token is refused [s since the epoch]; none: until it is revoked.
    Column("expires_at", Float),
    Index("ix_api_tokens_user_id", "user_id"),
)

projects = Table(
    "projects", metadata,
    Column("id", Integer, primary_key=True),
    Column("name", String(100), nullable=False, unique=True),
    Column("created_at", Float, nullable=False),
    Column("created_by", String(100), nullable=False),
)

designs = Table(
    "designs", metadata,
    Column("id", Integer, primary_key=True),
    Column("project_id", Integer, ForeignKey("projects.id"), nullable=False),
    Column("name", String(100), nullable=False),
    # the endpoint whose request every revision of the design is, e.g. /v1/machines/design
    Column("endpoint", String(100), nullable=False),
    Column("created_at", Float, nullable=False),
    Column("created_by", String(100), nullable=False),
    UniqueConstraint("project_id", "name", name="uq_designs_project_name"),
)

revisions = Table(
    "revisions", metadata,
    Column("id", Integer, primary_key=True),
    Column("design_id", Integer, ForeignKey("designs.id"), nullable=False),
    Column("number", Integer, nullable=False),
    Column("parent", Integer),
    Column("request", Text, nullable=False),
    Column("content_hash", String(64), nullable=False),
    Column("author", String(100), nullable=False),
    Column("created_at", Float, nullable=False),
    Column("message", Text, nullable=False),
    Column("answer", Text),
    Column("passed", Boolean),
    Column("record_pdf", LargeBinary),
    Column("state", String(16), nullable=False),
    Column("checked_by", String(100)),
    Column("checked_at", Float),
    Column("approved_by", String(100)),
    Column("approved_at", Float),
    Column("superseded_by", Integer),
    # Why a revision whose answer failed a check is signed anyway (the deviation the approver released).
    Column("deviation", Text),
    # Set on an imported revision: where it came from and what it claimed (state, signers), verified by nobody here.
    Column("imported_note", Text),
    UniqueConstraint("design_id", "number", name="uq_revisions_design_number"),
    Index("ix_revisions_content_hash", "content_hash"),
    Index("ix_revisions_created_at", "created_at"),
    # One approved revision per design, whatever two servers do at once.
    Index("uq_revisions_one_approved", "design_id", unique=True, sqlite_where=text("state = 'approved'"),
          postgresql_where=text("state = 'approved'")),
)

revision_comments = Table(
    "revision_comments", metadata,
    Column("id", Integer, primary_key=True),
    Column("revision_id", Integer, ForeignKey("revisions.id"), nullable=False),
    Column("author", String(100), nullable=False),
    Column("created_at", Float, nullable=False),
    # returned, check, approve, deviation or comment
    Column("kind", String(16), nullable=False),
    Column("text", Text, nullable=False),
    Index("ix_revision_comments_revision_id", "revision_id"),
)
